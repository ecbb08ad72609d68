//! The fields every message starts with (protocol version, entry count,
//! stamp), checked the same way for all of them and first.

use core::fmt;

use crate::PROTOCOL_VERSION;
use crate::reject_reason::RejectReason;
use crate::validation::{ValidationLimits, count_fits};

/// What is wrong with a message's header; every message's error type has it
/// as its `Header` variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeaderError {
    WrongProtocolVersion {
        found: u32,
    },
    CountExceedsCapacity {
        count: u32,
        capacity: usize,
    },
    StampFromFuture {
        stamp_ns: u64,
        now_ns: u64,
    },
    /// Older than the receiver accepts (a zero stamp included).
    Stale {
        stamp_ns: u64,
        now_ns: u64,
    },
}

impl HeaderError {
    /// The counter this rejection is counted under.
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::WrongProtocolVersion { .. } => RejectReason::WrongProtocolVersion,
            Self::CountExceedsCapacity { .. } => RejectReason::CountExceedsCapacity,
            Self::StampFromFuture { .. } => RejectReason::StampFromFuture,
            Self::Stale { .. } => RejectReason::Stale,
        }
    }

    /// One line naming the field of `message` (`part_states.count 65 …`).
    pub fn fmt_in(&self, message: &str, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::WrongProtocolVersion { found } => {
                write!(f, "{message}.protocol_version is {found}, expected {PROTOCOL_VERSION}")
            }
            Self::CountExceedsCapacity { count, capacity } => {
                write!(f, "{message}.count {count} exceeds the capacity {capacity}")
            }
            Self::StampFromFuture { stamp_ns, now_ns } => {
                write!(f, "{message}.stamp_ns {stamp_ns} is in the future (now {now_ns})")
            }
            Self::Stale { stamp_ns, now_ns } => {
                write!(f, "{message}.stamp_ns {stamp_ns} is older than the receiver accepts (now {now_ns})")
            }
        }
    }
}

/// Whether an old stamp is an error: yes for what the core receives, no
/// for its outputs (a late reader may still want the newest one).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OldStamps {
    Reject,
    Accept,
}

/// Version, count (with the capacity, for messages with entries), then
/// stamp: the first problem found.
pub(crate) fn check_header(
    protocol_version: u32,
    count: Option<(u32, usize)>,
    stamp_ns: u64,
    old: OldStamps,
    limits: &ValidationLimits,
) -> Result<(), HeaderError> {
    if protocol_version != PROTOCOL_VERSION {
        return Err(HeaderError::WrongProtocolVersion { found: protocol_version });
    }
    if let Some((count, capacity)) = count
        && !count_fits(count, capacity)
    {
        return Err(HeaderError::CountExceedsCapacity { count, capacity });
    }
    if limits.is_from_future(stamp_ns) {
        return Err(HeaderError::StampFromFuture { stamp_ns, now_ns: limits.now_ns });
    }
    if old == OldStamps::Reject && limits.is_stale(stamp_ns) {
        return Err(HeaderError::Stale { stamp_ns, now_ns: limits.now_ns });
    }
    Ok(())
}
