//! PickCommand: robot → feed cell, "I took the part at pose n". In
//! simulation with an external robot (`[rig.feed] robot = "external"`)
//! the simulator removes that part; on a real rig vision sees it go.

use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::PROTOCOL_VERSION;
use crate::feed_status::MAX_PICK_POSES;
use crate::header::{HeaderError, OldStamps, check_header};
use crate::reject_reason::RejectReason;
use crate::validation::ValidationLimits;

/// Robot → core: one pick done.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::PickCommand.v6"))]
pub struct PickCommand {
    pub protocol_version: u32,
    /// The pick pose taken from: an index of `FeedStatus::poses`.
    pub pose: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when it was sent.
    pub stamp_ns: u64,
    /// The part taken: `FeedStatus::poses[pose].part_id` when it was ready.
    /// The cell takes it only if that part is still the one ready there.
    pub part_id: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
}

const _: () = assert!(size_of::<PickCommand>() == 4 + 4 + 8 + 8 + 4 + 4);

/// Why a [`PickCommand`] was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PickCommandError {
    /// Protocol version or stamp.
    Header(HeaderError),
    PoseOutOfRange {
        pose: u32,
    },
    NoPart,
}

impl fmt::Display for PickCommandError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("pick_command", f),
            Self::PoseOutOfRange { pose } => {
                write!(f, "pick_command.pose {pose} is not below the capacity {MAX_PICK_POSES}")
            }
            Self::NoPart => f.write_str("pick_command.part_id is 0: no part"),
        }
    }
}

impl core::error::Error for PickCommandError {}

impl PickCommandError {
    /// The counter this rejection is counted under.
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::Header(h) => h.reason(),
            Self::PoseOutOfRange { .. } => RejectReason::CountExceedsCapacity,
            Self::NoPart => RejectReason::UnknownPart,
        }
    }
}

impl PickCommand {
    pub const fn new(pose: u32, part_id: u32, seq: u64, stamp_ns: u64) -> Self {
        Self { protocol_version: PROTOCOL_VERSION, pose, seq, stamp_ns, part_id, reserved: 0 }
    }

    /// Check the whole message. Allocation-free, constant time. Whether
    /// the part is ready at that pose is the cell's to check.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), PickCommandError> {
        check_header(self.protocol_version, None, self.stamp_ns, OldStamps::Reject, limits)
            .map_err(PickCommandError::Header)?;
        if self.pose as usize >= MAX_PICK_POSES {
            return Err(PickCommandError::PoseOutOfRange { pose: self.pose });
        }
        if self.part_id == 0 {
            return Err(PickCommandError::NoPart);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pick_names_a_pose_in_range_and_a_part() {
        let limits = ValidationLimits::new([1.0, 1.0], 1_000);
        assert_eq!(PickCommand::new(3, 7, 1, 1_000).validate(&limits), Ok(()));
        let far = PickCommand::new(MAX_PICK_POSES as u32, 7, 1, 1_000).validate(&limits);
        assert_eq!(far, Err(PickCommandError::PoseOutOfRange { pose: MAX_PICK_POSES as u32 }));
        assert_eq!(PickCommand::new(0, 0, 1, 1_000).validate(&limits), Err(PickCommandError::NoPart));
        let mut old = PickCommand::new(0, 7, 1, 1_000);
        old.protocol_version = 5;
        assert!(matches!(old.validate(&limits), Err(PickCommandError::Header(_))));
    }
}
