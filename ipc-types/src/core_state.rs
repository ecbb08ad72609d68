//! The core's operating state, carried on the wire as a `u32` code.

use core::fmt;

/// Operating state of the core. On the wire ([`crate::Telemetry::state`])
/// it is the `u32` code, because a Rust enum read from shared memory with an
/// unknown discriminant would be undefined behaviour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CoreState {
    /// Ports up, no motion requested yet.
    Idle,
    /// Playing schedules.
    Running,
    /// Inputs stale: the plate is held still until fresh input arrives.
    Hold,
    /// Stopped after an error; needs a restart.
    Fault,
}

impl CoreState {
    pub const IDLE_CODE: u32 = 0;
    pub const RUNNING_CODE: u32 = 1;
    pub const HOLD_CODE: u32 = 2;
    pub const FAULT_CODE: u32 = 3;

    pub const fn code(self) -> u32 {
        match self {
            Self::Idle => Self::IDLE_CODE,
            Self::Running => Self::RUNNING_CODE,
            Self::Hold => Self::HOLD_CODE,
            Self::Fault => Self::FAULT_CODE,
        }
    }

    /// The state of a wire code, `None` for an unknown code.
    pub const fn from_code(code: u32) -> Option<Self> {
        match code {
            Self::IDLE_CODE => Some(Self::Idle),
            Self::RUNNING_CODE => Some(Self::Running),
            Self::HOLD_CODE => Some(Self::Hold),
            Self::FAULT_CODE => Some(Self::Fault),
            _ => None,
        }
    }

    /// The name `upm status` prints (`idle`, `running`, `hold`, `fault`).
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Idle => "idle",
            Self::Running => "running",
            Self::Hold => "hold",
            Self::Fault => "fault",
        }
    }
}

impl fmt::Display for CoreState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}
