//! `upm calibrate plate`: learn how the real plate differs from its model,
//! from the parts already on it. A client of the running core like a
//! planner: it plays excitation schedules through `ExplicitSchedule`
//! ([`excite`]), watches the parts through `PartStates`, and fits the
//! plate's effective turning (a 3 × 3 twist correction for every center)
//! and its friction (a scale per part class and a low-order map) ([`fit`]).
//! The result is `rig_config::PlateCalibration`, which the core and the
//! planner load at start. This crate links the controller's model
//! (`rt-core`) and the wire contract, never the simulator: it cannot see a
//! simulated plate's hidden truth.

// Index loops mirror the matrix formulas; `!(x > 0.0)` deliberately rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

pub mod excite;
pub mod fit;
pub mod process;

pub use excite::{CalibrateSetup, ExciteParams, Exciter, Step};
pub use fit::{BurstMotion, Observation, RigModel};

/// Why a calibration was refused: one line each, naming what is missing.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CalibrateError {
    #[error("too few parts on the plate: {seen} seen, the fit needs at least {need}")]
    TooFewParts { seen: usize, need: usize },
    #[error("parts pinned at the fence: {pinned} of {parts} within reach of the plate's edge")]
    Pinned { pinned: usize, parts: usize },
    #[error("a part vanished {at_s:.2} s into the calibration: {seen} of {parts} seen")]
    Vanished { seen: usize, parts: usize, at_s: f64 },
    #[error("part_states.parts[{index}].{field} is not finite")]
    NonFinite { index: usize, field: &'static str },
    #[error("too little motion: the parts moved {:.0} % of what the model expects", fraction * 100.0)]
    TooLittleMotion { fraction: f64 },
    #[error(
        "the plate's turning is not determined: {determined} of {excited} excited centers located (the fit needs 4)"
    )]
    Turning { determined: usize, excited: usize },
    #[error("the friction fit did not converge")]
    Friction,
    #[error("the fit is implausible: {0}")]
    Implausible(String),
    #[error("bad calibration setup: {0}")]
    Setup(&'static str),
}
