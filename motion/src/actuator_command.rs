//! What the motor loop writes to a plate driver each tick.

/// Most actuators a rig may have (one command entry each).
pub const MAX_ACTUATORS: usize = 8;

/// One command per actuator (unused entries are 0). Positions are strokes
/// (m), velocities (m/s) are feed-forward, forces (N) are feed-forward.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ActuatorCommand {
    pub position: [f64; MAX_ACTUATORS],
    pub velocity: [f64; MAX_ACTUATORS],
    pub force: [f64; MAX_ACTUATORS],
}

impl ActuatorCommand {
    /// Everything at zero: the plate at home, at rest.
    pub const HOME: ActuatorCommand = ActuatorCommand {
        position: [0.0; MAX_ACTUATORS],
        velocity: [0.0; MAX_ACTUATORS],
        force: [0.0; MAX_ACTUATORS],
    };
}
