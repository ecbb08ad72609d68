//! CoreCommand: operator → core, e.g. `upm resume` after a driver fault.

use crate::header::{HeaderError, OldStamps, check_header};
use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::PROTOCOL_VERSION;
use crate::reject_reason::RejectReason;
use crate::validation::ValidationLimits;

/// Operator → core: one command.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::CoreCommand.v6"))]
pub struct CoreCommand {
    pub protocol_version: u32,
    /// [`CoreCommand::RESUME`], [`CoreCommand::STOP`] or [`CoreCommand::START`].
    pub command: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when it was sent.
    pub stamp_ns: u64,
}

const _: () = assert!(size_of::<CoreCommand>() == 4 + 4 + 8 + 8);

/// Why a [`CoreCommand`] was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoreCommandError {
    /// Protocol version, count or stamp.
    Header(HeaderError),

    UnknownCommand {
        command: u32,
    },
}

impl fmt::Display for CoreCommandError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("core_command", f),
            Self::UnknownCommand { command } => {
                write!(f, "core_command.command {command} is not a known command")
            }
        }
    }
}

impl core::error::Error for CoreCommandError {}

impl CoreCommandError {
    /// The counter this rejection is counted under.
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::Header(h) => h.reason(),
            Self::UnknownCommand { .. } => RejectReason::UnknownCommand,
        }
    }
}

impl CoreCommand {
    /// Leave a driver-fault hold (the plate resumes at the next cycle).
    pub const RESUME: u32 = 1;
    /// An operator's stop: at the next cycle boundary the plate is home,
    /// and it stays there (state idle) until [`CoreCommand::START`].
    pub const STOP: u32 = 2;
    /// End an operator's stop: the plate plays schedules again.
    pub const START: u32 = 3;

    pub const fn new(command: u32, seq: u64, stamp_ns: u64) -> Self {
        Self { protocol_version: PROTOCOL_VERSION, command, seq, stamp_ns }
    }

    /// Check the whole message. Allocation-free, constant time.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), CoreCommandError> {
        check_header(self.protocol_version, None, self.stamp_ns, OldStamps::Reject, limits)
            .map_err(CoreCommandError::Header)?;
        if !matches!(self.command, Self::RESUME | Self::STOP | Self::START) {
            return Err(CoreCommandError::UnknownCommand { command: self.command });
        }
        Ok(())
    }
}
