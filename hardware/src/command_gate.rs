//! What every driver's `write` and `hold` do: take a command through the
//! one limit policy and keep it, count what was clamped and refused, and
//! know whether the plate is held.

use crate::{ActuatorCommand, ActuatorLimits, PlateState, WriteError, apply_limits};

/// The command a driver holds, and the counts it reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommandGate {
    /// The last command accepted, within the limits (home while held).
    pub command: ActuatorCommand,
    /// Command entries clamped to a limit since start.
    pub clamped: u64,
    /// Commands refused (non-finite) since start.
    pub rejected: u64,
    /// Held at home since `hold`, until the next accepted write.
    pub holding: bool,
}

impl Default for CommandGate {
    fn default() -> Self {
        Self { command: ActuatorCommand::HOME, clamped: 0, rejected: 0, holding: false }
    }
}

impl CommandGate {
    /// `PlateDriver::write`: accept `command` within `limits` (clamped and
    /// counted), or refuse it and keep the previous one.
    pub fn write(&mut self, limits: &ActuatorLimits, command: &ActuatorCommand) -> Result<(), WriteError> {
        match apply_limits(limits, command, &mut self.command) {
            Ok(clamped) => {
                self.clamped += u64::from(clamped);
                self.holding = false;
                Ok(())
            }
            Err(e) => {
                self.rejected += 1;
                Err(e)
            }
        }
    }

    /// `PlateDriver::hold`: home at rest, no feed-forward.
    pub fn hold(&mut self) {
        self.command = ActuatorCommand::HOME;
        self.holding = true;
    }

    /// The counts and the hold flag into a reading.
    pub fn report(&self, state: &mut PlateState) {
        state.clamped = self.clamped;
        state.rejected = self.rejected;
        state.holding = self.holding;
    }
}
