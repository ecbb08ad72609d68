//! Why the core rejected an inbound message, as a stable code. Telemetry
//! counts rejections per code ([`crate::Telemetry::rejected_by_reason`]), so
//! an operator (or the sender) sees *why* messages are refused, not only
//! how many.

use core::fmt;

/// Why an inbound message was rejected. The discriminant is the index into
/// [`crate::Telemetry::rejected_by_reason`]; codes are never reused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RejectReason {
    WrongProtocolVersion = 0,
    CountExceedsCapacity = 1,
    /// A schedule with no slot.
    Empty = 2,
    StampFromFuture = 3,
    /// Older than the configured maximum age (a zero stamp included).
    Stale = 4,
    /// Older than a message of the same kind already accepted.
    OutOfOrder = 5,
    /// Same `seq` and stamp as the newest accepted message of its kind.
    Duplicate = 6,
    NonFinite = 7,
    OffPlate = 8,
    UnknownClass = 9,
    DuplicateId = 10,
    NotAFlag = 11,
    ConstrainsNothing = 12,
    TooManyCurls = 13,
    DeadlineBeforeStamp = 14,
    UnknownCenter = 15,
    KOutOfRange = 16,
    /// A request before any valid part states.
    NoPartStates = 17,
    /// A request names a part the newest part states do not contain.
    UnknownPart = 18,
    /// The solver refused the problem (out of its numeric range).
    Unsolvable = 19,
    /// The schedule cannot be played within the motion limits.
    MotionLimits = 20,
    /// The motion would exceed an actuator limit.
    ActuatorLimits = 21,
    /// The core's inbound ring was full (the solver fell behind a flood).
    Overflow = 22,
    /// iceoryx2 failed to deliver a sample.
    ReceiveError = 23,
    /// A core command with an unknown code.
    UnknownCommand = 24,
}

/// Length of [`crate::Telemetry::rejected_by_reason`] (room to grow).
pub const REJECT_REASONS: usize = 32;

impl RejectReason {
    /// Every reason, in code order.
    pub const ALL: [Self; 25] = [
        Self::WrongProtocolVersion,
        Self::CountExceedsCapacity,
        Self::Empty,
        Self::StampFromFuture,
        Self::Stale,
        Self::OutOfOrder,
        Self::Duplicate,
        Self::NonFinite,
        Self::OffPlate,
        Self::UnknownClass,
        Self::DuplicateId,
        Self::NotAFlag,
        Self::ConstrainsNothing,
        Self::TooManyCurls,
        Self::DeadlineBeforeStamp,
        Self::UnknownCenter,
        Self::KOutOfRange,
        Self::NoPartStates,
        Self::UnknownPart,
        Self::Unsolvable,
        Self::MotionLimits,
        Self::ActuatorLimits,
        Self::Overflow,
        Self::ReceiveError,
        Self::UnknownCommand,
    ];

    /// Index into the per-reason counters.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The name `upm status --json` uses.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::WrongProtocolVersion => "wrong_protocol_version",
            Self::CountExceedsCapacity => "count_exceeds_capacity",
            Self::Empty => "empty",
            Self::StampFromFuture => "stamp_from_future",
            Self::Stale => "stale",
            Self::OutOfOrder => "out_of_order",
            Self::Duplicate => "duplicate",
            Self::NonFinite => "non_finite",
            Self::OffPlate => "off_plate",
            Self::UnknownClass => "unknown_class",
            Self::DuplicateId => "duplicate_id",
            Self::NotAFlag => "not_a_flag",
            Self::ConstrainsNothing => "constrains_nothing",
            Self::TooManyCurls => "too_many_curls",
            Self::DeadlineBeforeStamp => "deadline_before_stamp",
            Self::UnknownCenter => "unknown_center",
            Self::KOutOfRange => "k_out_of_range",
            Self::NoPartStates => "no_part_states",
            Self::UnknownPart => "unknown_part",
            Self::Unsolvable => "unsolvable",
            Self::MotionLimits => "motion_limits",
            Self::ActuatorLimits => "actuator_limits",
            Self::Overflow => "overflow",
            Self::ReceiveError => "receive_error",
            Self::UnknownCommand => "unknown_command",
        }
    }
}

impl fmt::Display for RejectReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_dense_unique_and_fit_the_counters() {
        for (i, r) in RejectReason::ALL.iter().enumerate() {
            assert_eq!(r.index(), i);
        }
        assert!(RejectReason::ALL.len() <= REJECT_REASONS);
        let mut names: Vec<_> = RejectReason::ALL.iter().map(|r| r.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), RejectReason::ALL.len());
    }
}
