//! UPM's embedded physics simulator: the default
//! [`upm_hardware::PlateDriver`], with parts that slide on the plate under
//! Coulomb friction and a hidden truth of the plate's own.

// Index loops mirror the matrix formulas; `!(x > 0.0)` deliberately rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

pub mod feed;
pub mod rng;
pub mod sim;

pub use sim::{
    ActuatorKind, ActuatorModel, BodyShape, FRICTION_MAP_TERMS, FrictionMap, MAX_FRICTION_SCALE,
    MIN_FRICTION_SCALE, PartSpec, PartState, PlateTruth, SimConfig, SimConfigError, SimCounters, SimError,
    Simulator, TruthError, friction_scale_ok,
};
