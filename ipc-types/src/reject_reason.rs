//! Why the core rejected an inbound message, as a stable code. Telemetry
//! counts rejections per code ([`crate::Telemetry::rejected_by_reason`]), so
//! an operator (or the sender) sees *why* messages are refused, not only
//! how many.

crate::wire_code::wire_code! {
    /// Why an inbound message was rejected. The discriminant is the index into
    /// [`crate::Telemetry::rejected_by_reason`]; codes are never reused.
    pub enum RejectReason {
        WrongProtocolVersion = 0 => "wrong_protocol_version",
        CountExceedsCapacity = 1 => "count_exceeds_capacity",
        /// A schedule with no slot.
        Empty = 2 => "empty",
        StampFromFuture = 3 => "stamp_from_future",
        /// Older than the configured maximum age (a zero stamp included).
        Stale = 4 => "stale",
        /// Older than a message of the same kind already accepted.
        OutOfOrder = 5 => "out_of_order",
        /// Same `seq` and stamp as the newest accepted message of its kind.
        Duplicate = 6 => "duplicate",
        NonFinite = 7 => "non_finite",
        OffPlate = 8 => "off_plate",
        UnknownClass = 9 => "unknown_class",
        DuplicateId = 10 => "duplicate_id",
        NotAFlag = 11 => "not_a_flag",
        ConstrainsNothing = 12 => "constrains_nothing",
        TooManyCurls = 13 => "too_many_curls",
        DeadlineBeforeStamp = 14 => "deadline_before_stamp",
        UnknownCenter = 15 => "unknown_center",
        KOutOfRange = 16 => "k_out_of_range",
        /// A request before any valid part states.
        NoPartStates = 17 => "no_part_states",
        /// A request names a part the newest part states do not contain.
        UnknownPart = 18 => "unknown_part",
        /// The solver refused the problem (out of its numeric range).
        Unsolvable = 19 => "unsolvable",
        /// The schedule cannot be played within the motion limits.
        MotionLimits = 20 => "motion_limits",
        /// The motion would exceed an actuator limit.
        ActuatorLimits = 21 => "actuator_limits",
        /// The core's inbound ring was full (the solver fell behind a flood).
        Overflow = 22 => "overflow",
        /// iceoryx2 failed to deliver a sample.
        ReceiveError = 23 => "receive_error",
        /// A core command with an unknown code.
        UnknownCommand = 24 => "unknown_command",
        /// A part's outline is malformed (shape code, radius, vertices).
        BadShape = 25 => "bad_shape",
        /// A recipe's path is not UTF-8 or not absolute.
        BadPath = 26 => "bad_path",
        /// A recipe the cell cannot switch to: unreadable, invalid for
        /// this plate, or of other part classes.
        BadRecipe = 27 => "bad_recipe",
    }
}

/// Length of [`crate::Telemetry::rejected_by_reason`] (room to grow).
pub const REJECT_REASONS: usize = 32;

impl RejectReason {
    /// Index into the per-reason counters.
    pub const fn index(self) -> usize {
        self as usize
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
