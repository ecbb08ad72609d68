//! Planners: a small trait, and the built-in planners of the paper's
//! experiments. A planner sees only part states and writes force requests;
//! an external planner is a separate binary that implements [`Planner`] and
//! calls [`run::run_planner`] (see `clients/examples/external_planner.rs`).

pub mod goal;
pub mod process;
pub mod run;

use ipc_types::{ForceRequest, PartStates};
use serde::{Deserialize, Serialize};

pub use goal::{GoalPlanner, Mode};

/// What every planner implements.
pub trait Planner: Send {
    fn name(&self) -> &'static str;
    /// Fill `out`'s entries from the newest part states at time `t` (s
    /// since the planner's first frame). Returns false when it has nothing
    /// to ask this frame.
    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool;
}

/// `[planner]` of a scenario: which planner and its tunables.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct PlannerParams {
    /// track, sort, spin or local.
    pub name: String,
    /// Speed limit of the parts (m/s); keeps them well below the plate's
    /// speed, as the friction model assumes.
    pub max_speed: f64,
    /// Position gain: desired speed per metre of error (1/s).
    pub position_gain: f64,
    /// Velocity gain: desired acceleration per m/s of speed error (1/s).
    pub velocity_gain: f64,
    /// Largest requested force as a fraction of μmg.
    pub max_force_fraction: f64,
    /// Parts' μmg (N) and mass (kg), to turn accelerations into forces.
    pub mu_m_g: f64,
    pub mass: f64,
    /// sort: |x| a part must pass on its side.
    pub sort_x: f64,
    /// sort: parts driven at once (the nearest to their side first); the
    /// rest are left unconstrained. The paper drives all of them.
    pub sort_batch: usize,
    /// sort: that many other parts nearest to the driven ones are held where
    /// they were last driven (a PD, like the driven parts), so the field
    /// does not drag them along.
    pub sort_hold: usize,
    /// sort: a part steers sideways around parts of the other class that
    /// are ahead of it closer than this (m; 0 turns dodging off) ...
    pub sort_dodge_distance: f64,
    /// ... and within this (m) of its lane.
    pub sort_dodge_width: f64,
    /// track: rectangles (centre x, centre y, width, height) per part id 1, 2.
    pub track_rects: Vec<[f64; 4]>,
    /// track: speed along the path (m/s).
    pub track_speed: f64,
    /// spin: the part and the angle (rad) it turns to, in place.
    pub spin_id: u32,
    pub spin_angle: f64,
    /// spin: curl per radian of angle error (N/m/rad), and its limit.
    pub spin_gain: f64,
    pub max_curl: f64,
    /// local: the part that moves and its goal.
    pub local_id: u32,
    pub local_goal: [f64; 2],
}

impl Default for PlannerParams {
    fn default() -> Self {
        Self {
            name: "sort".into(),
            max_speed: 0.03,
            position_gain: 1.0,
            velocity_gain: 8.0,
            max_force_fraction: 0.15,
            mu_m_g: 0.1,
            mass: 0.1 / (0.25 * 9.81),
            sort_x: 0.6,
            sort_batch: ipc_types::MAX_PARTS,
            sort_hold: 0,
            sort_dodge_distance: 0.15,
            sort_dodge_width: 0.06,
            track_rects: vec![[-0.45, 0.0, 0.4, 0.3], [0.45, 0.0, 0.4, 0.3]],
            track_speed: 0.02,
            spin_id: 1,
            spin_angle: std::f64::consts::FRAC_PI_2,
            spin_gain: 0.2,
            max_curl: 0.05,
            local_id: 1,
            local_goal: [0.3, 0.2],
        }
    }
}

/// A built-in planner by name.
pub fn planner_by_name(params: &PlannerParams) -> anyhow::Result<Box<dyn Planner>> {
    let mode = match params.name.as_str() {
        "sort" => Mode::Sort,
        "track" => Mode::Track,
        "spin" => Mode::Spin,
        "local" => Mode::Local,
        other => anyhow::bail!("planner.name {other:?}: expected track, sort, spin or local"),
    };
    Ok(Box::new(GoalPlanner::new(mode, params.clone())?))
}
