//! What a plate driver reports each tick.

use crate::{MAX_ACTUATORS, Pose, Twist};

/// What a driver reports each tick.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PlateState {
    /// Ticks completed by the driver (simulated or hardware clock).
    pub tick: u64,
    /// Driver time (s).
    pub time: f64,
    pub pose: Pose,
    pub velocity: Twist,
    pub actuator_position: [f64; MAX_ACTUATORS],
    /// Force each drive applied over the last tick (N): the command's
    /// feed-forward plus the drive's own servo effort.
    pub actuator_force: [f64; MAX_ACTUATORS],
    /// Command entries clamped to a limit since start.
    pub clamped: u64,
    /// Commands rejected (non-finite) since start.
    pub rejected: u64,
    /// True while the driver holds the plate at home after the driver's `hold`.
    pub holding: bool,
}
