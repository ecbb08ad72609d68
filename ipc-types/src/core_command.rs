//! CoreCommand: operator → core, e.g. `upm resume` after a driver fault.

use core::fmt;

use iceoryx2::prelude::ZeroCopySend;

use crate::PROTOCOL_VERSION;
use crate::reject_reason::RejectReason;
use crate::validation::ValidationLimits;

/// Operator → core: one command.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, ZeroCopySend)]
#[type_name("upm::CoreCommand.v2")]
pub struct CoreCommand {
    pub protocol_version: u32,
    /// [`CoreCommand::RESUME`].
    pub command: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when it was sent.
    pub stamp_ns: u64,
}

const _: () = assert!(size_of::<CoreCommand>() == 4 + 4 + 8 + 8);

/// Why a [`CoreCommand`] was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoreCommandError {
    WrongProtocolVersion { found: u32 },
    UnknownCommand { command: u32 },
    StampFromFuture { stamp_ns: u64, now_ns: u64 },
    Stale { stamp_ns: u64, now_ns: u64 },
}

impl fmt::Display for CoreCommandError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::WrongProtocolVersion { found } => {
                write!(f, "core_command.protocol_version is {found}, expected {PROTOCOL_VERSION}")
            }
            Self::UnknownCommand { command } => {
                write!(f, "core_command.command {command} is not a known command")
            }
            Self::StampFromFuture { stamp_ns, now_ns } => {
                write!(f, "core_command.stamp_ns {stamp_ns} is in the future (now {now_ns})")
            }
            Self::Stale { stamp_ns, now_ns } => {
                write!(f, "core_command.stamp_ns {stamp_ns} is older than the core accepts (now {now_ns})")
            }
        }
    }
}

impl core::error::Error for CoreCommandError {}

impl CoreCommandError {
    /// The counter this rejection is counted under.
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::WrongProtocolVersion { .. } => RejectReason::WrongProtocolVersion,
            Self::UnknownCommand { .. } => RejectReason::UnknownCommand,
            Self::StampFromFuture { .. } => RejectReason::StampFromFuture,
            Self::Stale { .. } => RejectReason::Stale,
        }
    }
}

impl CoreCommand {
    /// Leave a driver-fault hold (the plate resumes at the next cycle).
    pub const RESUME: u32 = 1;

    pub const fn new(command: u32, seq: u64, stamp_ns: u64) -> Self {
        Self { protocol_version: PROTOCOL_VERSION, command, seq, stamp_ns }
    }

    /// Check the whole message. Allocation-free, constant time.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), CoreCommandError> {
        if self.protocol_version != PROTOCOL_VERSION {
            return Err(CoreCommandError::WrongProtocolVersion { found: self.protocol_version });
        }
        if self.command != Self::RESUME {
            return Err(CoreCommandError::UnknownCommand { command: self.command });
        }
        if limits.is_from_future(self.stamp_ns) {
            return Err(CoreCommandError::StampFromFuture { stamp_ns: self.stamp_ns, now_ns: limits.now_ns });
        }
        if limits.is_stale(self.stamp_ns) {
            return Err(CoreCommandError::Stale { stamp_ns: self.stamp_ns, now_ns: limits.now_ns });
        }
        Ok(())
    }
}
