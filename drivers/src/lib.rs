//! Plate drivers for UPM: the embedded physics simulator (the default
//! driver), an ideal mock, motion playback and the conformance suite every
//! [`rt_core::driver::PlateDriver`] runs.

// Index loops mirror the matrix formulas; `!(x > 0.0)` deliberately rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

pub mod conformance;
pub mod ideal;
pub mod playback;
pub mod rng;
pub mod sim;

pub use ideal::IdealDriver;
pub use sim::{
    ActuatorModel, FRICTION_MAP_TERMS, FrictionMap, MAX_FRICTION_SCALE, MIN_FRICTION_SCALE, PartSpec,
    PartState, PlateTruth, Shape, SimConfig, SimConfigError, SimCounters, SimError, Simulator, TruthError,
    friction_scale_ok,
};
