//! `upm solve` JSON contract (ARCHITECTURE.md §7): parse, solve, serialize.
//! Each center's bound on |k| is the smaller of `k_max` and what it can
//! play on the rig `upm validate` plays on (its motion and actuator
//! limits), as the core bounds it; the output names the centers whose
//! bound that lowered.

use upm_motion::{
    LinearizeAbout, MAX_DYNAMICS_STEPS, MAX_DYNAMICS_SUBSTEPS, MAX_FRICTION_SCALE, MIN_FRICTION_SCALE,
    PartDynamics, PartDynamicsParams, PartMotion,
};
use upm_motion::{PlateMotion, Rig, playable_k};
use upm_solver::{
    CurlConstraint, ForceConstraint, PartShape, Problem, Solution, Solver, SolverCapacity, SolverParams,
};

use crate::validate::setup::ValidateSetup;
use serde::{Deserialize, Serialize};

/// Default bound on |k_j| when the input does not give `k_max`.
pub const DEFAULT_K_MAX: f64 = 0.95;

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartInput {
    pub position: [f64; 2],
    #[serde(default)]
    pub force: Option<[f64; 2]>,
    /// The part's contact patch; a point (the paper's model) if absent.
    #[serde(default)]
    pub shape: ShapeInput,
    /// The curl whose torque on this part's patch it should feel.
    #[serde(default)]
    pub curl: Option<f64>,
    /// The part's μ over the model's (a plate calibration's scale where it
    /// stands; 1 if absent; within 0.2..3). Its `force` stays in the model's units; with
    /// `part_dynamics`, how far it slides within the cycle goes with it.
    #[serde(default)]
    pub friction: Option<f64>,
}

/// `"point"`, `{"disc": {"radius": R}}` or `{"polygon": {"vertices":
/// [[x, y], …]}}`, vertices relative to the part's position.
#[derive(Debug, Clone, Default, Deserialize, PartialEq)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeInput {
    #[default]
    Point,
    Disc {
        radius: f64,
    },
    Polygon {
        vertices: Vec<[f64; 2]>,
    },
}

impl ShapeInput {
    /// The solver's shape; the error names the problem, not the field.
    pub fn to_shape(&self) -> Result<PartShape, upm_solver::ShapeError> {
        let s = match self {
            Self::Point => PartShape::Point,
            Self::Disc { radius } => PartShape::Disc { radius: *radius },
            Self::Polygon { vertices } => PartShape::polygon(vertices)?,
        };
        s.check()?;
        Ok(s)
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurlInput {
    pub position: [f64; 2],
    pub curl: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolveInput {
    pub mu_m_g: f64,
    pub centers: Vec<[f64; 2]>,
    #[serde(default)]
    pub parts: Vec<PartInput>,
    #[serde(default)]
    pub curls: Vec<CurlInput>,
    #[serde(default)]
    pub k_max: Option<f64>,
    /// Correct each part's requested force and own curl for the velocity
    /// and spin it picks up through the cycle
    /// (`upm_motion::cycle_mean_twist`), and report what that model
    /// predicts (`predicted_forces`, `predicted_curls`).
    #[serde(default)]
    pub part_dynamics: bool,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Achieved {
    pub forces: Vec<[f64; 2]>,
    pub curls: Vec<f64>,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SolveOutput {
    pub k: Vec<f64>,
    pub order: Vec<usize>,
    pub priority: Vec<f64>,
    pub achieved: Achieved,
    /// ‖A·K − b‖ over the request: force rows in N, curl rows in N/m.
    pub residual: f64,
    pub rank: usize,
    /// Estimated κ₂; rank-deficient systems report f64::MAX (JSON has no ∞).
    pub condition: f64,
    /// A bound keeps the request from being met: a bound is active and the
    /// residual exceeds `solver::SATURATION_TOLERANCE` of the request's norm.
    pub saturated: bool,
    /// Centers whose |k| is at their bound, whether or not the request is met.
    pub at_bound: usize,
    /// Wall time of `Solver::solve` alone (µs), on a fresh solver (cold).
    pub solve_time_us: f64,
    /// Free-block solves of the bounded path (0 on the exact path).
    pub iterations: usize,
    /// Per center, the bound on |k| it was solved under: `k_max`, or less
    /// where the rig cannot play that much about it.
    pub k_bounds: Vec<f64>,
    /// The centers whose bound the rig lowered below `k_max`.
    pub k_lowered: Vec<usize>,
    /// With `part_dynamics`: per part, the cycle's average force the part
    /// model predicts for this answer (empty otherwise).
    pub predicted_forces: Vec<[f64; 2]>,
    /// With `part_dynamics`: for each part asked a curl (in part order),
    /// the curl its patch's predicted spin-up shows (null for a point).
    pub predicted_curls: Vec<Option<f64>>,
    /// With `part_dynamics`: the step whose answer this is (0 = the first
    /// answer; the steps stop at a lack of 0.1 % or after 8, and the one
    /// with the least lack is answered), and that lack: the largest
    /// |predicted − asked| over |asked| (+ 0.005 μmg for forces). The play
    /// `order` is the first answer's throughout; `priority` is this one's.
    pub dynamics_steps: usize,
    pub dynamics_lack: f64,
}

/// Input errors, each naming the JSON field, one line each.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// Shown without a `source` chain so the message stays one line.
    #[error("{path}: {message}")]
    Json { path: String, message: String },
    #[error("{0}")]
    Solve(upm_solver::SolveError),
    #[error("centers[{center}]: the rig cannot play any k about it within its motion and actuator limits")]
    Unplayable { center: usize },
    #[error("the validation rig: {0}")]
    Rig(String),
}

/// Parse the JSON text. Numbers that overflow f64 (e.g. 1e999), `null`
/// where a number is needed, and unknown fields are all rejected here.
pub fn parse(text: &str) -> Result<SolveInput, InputError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    let input: SolveInput = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        // Top level (or an empty key): name the document itself.
        let path = if path == "." || path.is_empty() { "input".to_owned() } else { path };
        InputError::Json { path: printable(&path), message: printable(&e.into_inner().to_string()) }
    })?;
    Ok(input)
}

/// Control characters (a newline inside a key, say) shown escaped, so an
/// error stays on one line.
fn printable(s: &str) -> String {
    s.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
}

impl SolveInput {
    pub fn k_max(&self) -> f64 {
        self.k_max.unwrap_or(DEFAULT_K_MAX)
    }

    /// Every part, with its shape.
    pub fn force_constraints(&self) -> Result<Vec<ForceConstraint>, InputError> {
        self.parts
            .iter()
            .enumerate()
            .map(|(i, p)| {
                Ok(ForceConstraint { position: p.position, force: p.force, shape: part_shape(p, i)? })
            })
            .collect()
    }

    /// Each part at rest with its friction; the error names
    /// `parts[i].friction`.
    pub fn part_motions(&self) -> Result<Vec<PartMotion>, InputError> {
        self.parts
            .iter()
            .enumerate()
            .map(|(i, p)| match p.friction {
                None => Ok(PartMotion::default()),
                Some(f) if (MIN_FRICTION_SCALE..=MAX_FRICTION_SCALE).contains(&f) => {
                    Ok(PartMotion { friction: f, ..PartMotion::default() })
                }
                Some(f) => Err(InputError::Json {
                    path: format!("parts[{i}].friction"),
                    message: format!("{f} is not within {MIN_FRICTION_SCALE}..{MAX_FRICTION_SCALE}"),
                }),
            })
            .collect()
    }

    /// The top-level curls (at points), then each part's own curl on its
    /// patch, in part order.
    pub fn curl_constraints(&self) -> Result<Vec<CurlConstraint>, InputError> {
        let top = self
            .curls
            .iter()
            .map(|q| Ok(CurlConstraint { position: q.position, curl: q.curl, shape: PartShape::Point }));
        let own = self.parts.iter().enumerate().filter_map(|(i, p)| {
            p.curl.map(|curl| Ok(CurlConstraint { position: p.position, curl, shape: part_shape(p, i)? }))
        });
        top.chain(own).collect()
    }
}

/// Part `i`'s shape; the error names `parts[i].shape`.
pub(crate) fn part_shape(p: &PartInput, i: usize) -> Result<PartShape, InputError> {
    p.shape
        .to_shape()
        .map_err(|e| InputError::Json { path: format!("parts[{i}].shape"), message: e.to_string() })
}

/// Per center, the largest |k| ≤ `k_max` it can play on `setup`'s rig
/// (`upm_motion::playable_k`). A center that is not a finite point is
/// left at `k_max`: the solver refuses it by name.
pub fn playable_bounds(input: &SolveInput, setup: &ValidateSetup) -> Result<Vec<f64>, InputError> {
    let mut probe = PlateMotion::new(setup.motion).map_err(|e| InputError::Rig(e.to_string()))?;
    let rig = Rig::new(setup.sim.rig).map_err(|e| InputError::Rig(e.to_string()))?;
    let k_max = input.k_max();
    let mut bounds = Vec::with_capacity(input.centers.len());
    for (center, &c) in input.centers.iter().enumerate() {
        if !(c[0].is_finite() && c[1].is_finite() && k_max.is_finite() && k_max > 0.0) {
            bounds.push(k_max);
            continue;
        }
        let u = playable_k(&mut probe, &rig, c, k_max);
        if u.is_nan() || u <= 0.0 {
            return Err(InputError::Unplayable { center });
        }
        bounds.push(u);
    }
    Ok(bounds)
}

/// Solve one input with the default capacity and parameters, each center
/// bounded by what it can play on the validation rig. With
/// `part_dynamics`, the core's correction (`upm_motion::PartDynamics`)
/// from rest, on the validation rig's drives, finely: 32 substeps, up to
/// 8 steps, every part over its patch.
pub fn solve(input: &SolveInput) -> Result<SolveOutput, InputError> {
    let setup = ValidateSetup::default();
    let k_bounds = playable_bounds(input, &setup)?;
    let (parts, curls) = (input.force_constraints()?, input.curl_constraints()?);
    let motions = input.part_motions()?;
    let problem = Problem {
        mu_m_g: input.mu_m_g,
        k_max: input.k_max(),
        centers: &input.centers,
        parts: &parts,
        curls: &curls,
        k_bounds: &k_bounds,
    };
    let mut solver = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut solution = solver.new_solution();
    let started = std::time::Instant::now();
    let result = solver.solve(&problem, &mut solution);
    let solve_time_us = started.elapsed().as_secs_f64() * 1e6;
    result.map_err(InputError::Solve)?;
    let mut dynamics = None;
    if input.part_dynamics {
        // The drives as the rig is specified (not as any hidden truth has them).
        let follow = setup.sim.drive_servo().servo;
        let params = PartDynamicsParams {
            steps: MAX_DYNAMICS_STEPS,
            about: LinearizeAbout::Rest,
            mu_g: setup.sim.mu_kinetic * setup.sim.gravity,
            substeps: MAX_DYNAMICS_SUBSTEPS,
            follow,
            patch_forces: true,
            max_work: u64::MAX,
        };
        let probe = PlateMotion::new(setup.motion).map_err(|e| InputError::Rig(e.to_string()))?;
        let mut d = PartDynamics::new(params, probe, input.centers.len(), solver.new_solution())
            .map_err(|e| InputError::Rig(e.to_string()))?;
        // From rest, with each part's friction. A part's own curl is its
        // part's; the top-level ones are at points (no part).
        let own = input.parts.iter().enumerate().filter(|(_, p)| p.curl.is_some()).map(|(i, _)| i);
        let curl_parts: Vec<usize> = std::iter::repeat_n(usize::MAX, input.curls.len()).chain(own).collect();
        let c = d.correct(&mut solver, &problem, &motions, &curl_parts, &mut solution);
        dynamics = Some((d, c));
    }
    let mut out = to_output(&solution, solve_time_us);
    out.k_lowered = (0..k_bounds.len()).filter(|&j| k_bounds[j] < input.k_max()).collect();
    out.k_bounds = k_bounds;
    if let Some((d, c)) = dynamics {
        out.predicted_forces = d.predicted_forces().to_vec();
        // Only the parts' own curls: the top-level ones are at points.
        out.predicted_curls = d.predicted_curls().get(input.curls.len()..).unwrap_or_default().to_vec();
        (out.dynamics_steps, out.dynamics_lack) = (c.kept as usize, c.lack);
    }
    Ok(out)
}

/// Issue 25's measure of a force's error (the benches and the correction
/// all judge a force by it).
pub use upm_motion::relative_force_error;

pub fn to_output(s: &Solution, solve_time_us: f64) -> SolveOutput {
    SolveOutput {
        k: s.k().to_vec(),
        order: s.order().iter().map(|&j| j as usize).collect(),
        priority: s.priority().to_vec(),
        achieved: Achieved { forces: s.achieved_forces().to_vec(), curls: s.achieved_curls().to_vec() },
        residual: s.residual,
        rank: s.rank,
        condition: if s.condition.is_finite() { s.condition } else { f64::MAX },
        saturated: s.saturated,
        at_bound: s.at_bound,
        solve_time_us,
        iterations: s.iterations,
        k_bounds: Vec::new(),
        k_lowered: Vec::new(),
        predicted_forces: Vec::new(),
        predicted_curls: Vec::new(),
        dynamics_steps: 0,
        dynamics_lack: 0.0,
    }
}
