//! Closed plate motion (ARCHITECTURE.md §2 "How a slot really moves the plate").
//!
//! A schedule (centers in play order, each with its k_j) becomes a
//! [`PlateMotion`]: one slot per entry, each a time-asymmetric rotation about
//! C_j — slow one way for t_s, fast back for t_f, same angle both ways, with
//! k_j = (t_s − t_f)/τ and the slow direction = sign(k_j). Every slot starts
//! and ends exactly at home, so every cycle is closed.
//!
//! Velocity profiles are piecewise linear (bounded acceleration) with every
//! knot on a motor tick except the mid-slot reversal, which sits inside one
//! straight segment: a plate holding a constant acceleration per tick
//! reproduces the profile exactly and reverses at exactly t_s (this is what
//! keeps k unbiased at 10 kHz).
//!
//! [`PlateMotion::sample_tick`] is the motor-thread call: no allocation, no
//! panic, O(1). [`Rig`] maps poses to actuator commands and back.

// Index loops mirror the matrix formulas; `!(x > 0.0)` deliberately rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

mod actuator_command;
mod cycle_entries;
mod inertia_estimate;
mod params;
mod part_drift;
mod part_dynamics;
mod part_dynamics_params;
mod part_friction;
mod plan;
mod plate_follow;
mod plate_path;
mod plate_state;
mod playable;
mod pose;
mod profile;
mod rig;
mod setpoint;

pub use actuator_command::{ActuatorCommand, MAX_ACTUATORS};
pub use cycle_entries::fill_entries;
pub use inertia_estimate::{InertiaEstimate, InertiaParams, InertiaParamsError};
pub use params::{MotionParams, ParamsError};
pub use part_drift::{DriftParams, PlateTrace, TraceTooLong, cycle_mean_acceleration, cycle_mean_twist};
pub use part_dynamics::{Correction, PartDynamics, PartMotion, relative_force_error};
pub use part_dynamics_params::{
    LinearizeAbout, MAX_CORRECTION_WORK, MAX_DYNAMICS_STEPS, MAX_DYNAMICS_SUBSTEPS, MAX_TRACE_PIECES,
    PartDynamicsError, PartDynamicsParams,
};
pub use part_friction::{
    FRICTION_MAP_TERMS, MAX_FRICTION_CLASSES, MAX_FRICTION_SCALE, MIN_FRICTION_SCALE, PartFriction,
    PartFrictionError,
};
pub use plan::{MAX_SLOTS, MotionError, PlateMotion, ScheduleEntry, Slot};
pub use plate_follow::PlateFollow;
pub use plate_state::PlateState;
pub use playable::playable_k;
pub use pose::{PlateSample, Pose, Twist, sin_cos};
pub use profile::{MAX_KNOTS, Profile, ProfilePoint};
pub use rig::{Actuator, Rig, RigError, RigParams};
pub use setpoint::next_command;
