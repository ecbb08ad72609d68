//! The driver boundary, ros2_control style: each motor tick is
//! read → update → write. A real rig driver and the simulator implement the
//! same [`PlateDriver`]; the generic [`conformance`] suite checks any
//! implementation, and [`IdealDriver`] runs the whole chain without physics.
//!
//! Limit policy (shared by every driver through [`apply_limits`]): a command
//! with a non-finite entry is rejected and the previous command stays in
//! force; finite entries beyond a stroke, velocity or force limit are clamped
//! to the limit and counted in [`PlateState::clamped`]. So no schedule can
//! drive an actuator past its limits, and clamping is never silent.

// Index loops mirror the matrix formulas; `!(x > 0.0)` deliberately rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

mod command_gate;
pub mod conformance;
mod health;
pub mod ideal;
mod limits;
pub mod playback;

pub use command_gate::CommandGate;
pub use health::{BusState, DriverHealth, DriverKind};
pub use ideal::IdealDriver;
pub use limits::{ActuatorLimits, apply_limits};
pub use upm_motion::{ActuatorCommand, MAX_ACTUATORS, PlateState, Pose, Twist};

use core::fmt;

/// Why a read failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReadError {
    /// No fresh measurement this tick.
    NotReady,
    /// The hardware reports a fault; the caller should hold.
    Fault,
}

/// Why a write was refused (the previous command stays in force).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WriteError {
    NonFinite { actuator: usize },
    Fault,
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotReady => f.write_str("driver read: no fresh measurement"),
            Self::Fault => f.write_str("driver read: hardware fault"),
        }
    }
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite { actuator } => {
                write!(f, "driver write: non-finite command for actuator {actuator}")
            }
            Self::Fault => f.write_str("driver write: hardware fault"),
        }
    }
}

impl core::error::Error for ReadError {}
impl core::error::Error for WriteError {}

/// A plate driver. `read`, `write`, `hold` and `advance` are called from the
/// motor thread: implementations must not allocate, lock, log or panic.
pub trait PlateDriver {
    /// Actuator count and limits enforced at this boundary.
    fn limits(&self) -> ActuatorLimits;

    /// Tick period (s) the driver expects between writes.
    fn tick_period(&self) -> f64;

    /// Fill `state` with the latest measurement.
    fn read(&mut self, state: &mut PlateState) -> Result<(), ReadError>;

    /// Apply a command (clamped to the limits, see module docs).
    fn write(&mut self, command: &ActuatorCommand) -> Result<(), WriteError>;

    /// Command home at rest and zero feed-forward until the next `write`.
    fn hold(&mut self);

    /// Let one tick of time pass: a simulator integrates one tick, a
    /// fieldbus driver exchanges its process data (the command just
    /// written goes out, the next reading comes in).
    fn advance(&mut self) {}

    /// How much later (positive) or earlier the motor loop's next deadline
    /// should be, once, to stay in phase with a clock the hardware keeps
    /// (a fieldbus's distributed clocks). 0 for drivers that follow the
    /// motor loop. Bounded by the driver to a small part of a tick.
    fn clock_correction_ns(&mut self) -> i64 {
        0
    }

    /// Bus state, faults and lost frames ([`DriverHealth::SIMULATED`] for
    /// drivers without a bus).
    fn health(&self) -> DriverHealth {
        DriverHealth::SIMULATED
    }
}
