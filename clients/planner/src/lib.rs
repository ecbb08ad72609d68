//! Planners: a small trait, the built-in planners of the paper's
//! experiments, and the process loop that runs one. A planner sees only
//! part states and writes force requests; it links `ipc-types` and nothing
//! of the core or the simulator. An external planner is a separate binary
//! that implements [`Planner`] and calls [`run::run_planner`] (see
//! `examples/own-planner/gather.rs` at the repository's root).
//!
//! The built-in planners are chosen by [`PlannerConfig`], the `[planner]`
//! section of the rig config: `name` picks the planner, the other fields
//! are that planner's parameters.

pub mod adapt_counts;
pub mod adaptive;
pub mod args;
pub mod calibrated;
pub mod drive;
pub mod local;
pub mod pick_assignment;
pub mod present;
pub mod queue_spots;
pub mod registry;
pub mod run;
pub mod sort;
pub mod sort_paper;
pub mod spin;
pub mod track;

use ipc_types::{ForceRequest, PartStates};

pub use drive::DriveParams;
pub use registry::PlannerConfig;

/// What every planner implements.
pub trait Planner: Send {
    fn name(&self) -> &'static str;
    /// Fill `out`'s entries from the newest part states at time `t` (s
    /// since the planner's first frame). Returns false when it has nothing
    /// to ask this frame.
    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool;
    /// Each part's friction scale as this planner believes it, where the
    /// part was last seen (μ over the nominal), if it learns one.
    fn friction_estimates(&self) -> Vec<(u32, f64)> {
        Vec::new()
    }
    /// What the learning did with its windows, if it learns.
    fn learning_counts(&self) -> Option<adapt_counts::AdaptCounts> {
        None
    }
    /// The feed cell now runs the recipe at `path` (the core announces it
    /// on `upm/recipe/active`, at start and after each changeover).
    /// Ok(true): this planner switched to it; Ok(false): it runs no recipe,
    /// or already this one; Err: why it cannot follow (it keeps its own).
    fn recipe_changed(&mut self, path: &str) -> Result<bool, String> {
        let _ = path;
        Ok(false)
    }
}
