//! ExplicitSchedule: planner → core, a cycle given slot by slot, for
//! planners that bypass the solver.

use crate::header::{HeaderError, OldStamps};
use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::capacity::MAX_SLOTS;
use crate::reject_reason::RejectReason;
use crate::validation::ValidationLimits;

/// One slot: a rotation about configured center `center_index` with signed
/// intensity `k` (k > 0 = CCW), |k| ≤ 1.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::ExplicitSlot.v6"))]
pub struct ExplicitSlot {
    /// Index into the rig's configured centers.
    pub center_index: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
    pub k: f64,
}

const _: () = assert!(size_of::<ExplicitSlot>() == 4 + 4 + 8);

impl ExplicitSlot {
    pub const ZERO: Self = Self::new(0, 0.0);

    pub const fn new(center_index: u32, k: f64) -> Self {
        Self { center_index, reserved: 0, k }
    }
}

/// Planner → core: the slots of one closed cycle, in play order.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::ExplicitSchedule.v6"))]
pub struct ExplicitSchedule {
    pub protocol_version: u32,
    /// Number of used entries of `slots`; at least 1.
    pub count: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when the planner made the schedule.
    pub stamp_ns: u64,
    pub slots: [ExplicitSlot; MAX_SLOTS],
}

const _: () = assert!(size_of::<ExplicitSchedule>() == 4 + 4 + 2 * 8 + MAX_SLOTS * size_of::<ExplicitSlot>());

/// Why an [`ExplicitSchedule`] was rejected. Indices refer to `slots`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExplicitScheduleError {
    /// Protocol version, count or stamp.
    Header(HeaderError),

    /// A cycle needs at least one slot (its duration is divided among them).
    Empty,

    UnknownCenter {
        index: usize,
        center_index: u32,
    },
    NonFinite {
        index: usize,
        field: &'static str,
    },
    /// |k| exceeds the limits' k_max (or 1).
    KOutOfRange {
        index: usize,
    },
}

impl fmt::Display for ExplicitScheduleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("explicit_schedule", f),
            Self::Empty => write!(f, "explicit_schedule.count is 0, a cycle needs at least one slot"),
            Self::UnknownCenter { index, center_index } => write!(
                f,
                "explicit_schedule.slots[{index}].center_index {center_index} is not a configured center"
            ),
            Self::NonFinite { index, field } => {
                write!(f, "explicit_schedule.slots[{index}].{field} is not finite")
            }
            Self::KOutOfRange { index } => write!(f, "explicit_schedule.slots[{index}].k exceeds k_max"),
        }
    }
}

impl core::error::Error for ExplicitScheduleError {}

impl ExplicitScheduleError {
    /// The counter this rejection is counted under.
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::Header(h) => h.reason(),
            Self::Empty => RejectReason::Empty,
            Self::UnknownCenter { .. } => RejectReason::UnknownCenter,
            Self::NonFinite { .. } => RejectReason::NonFinite,
            Self::KOutOfRange { .. } => RejectReason::KOutOfRange,
        }
    }
}

crate::counted_message::counted_message!(
    ExplicitSchedule,
    slots / slots_mut: [ExplicitSlot; MAX_SLOTS],
    new {}
);

impl ExplicitSchedule {
    /// Check the whole message; the first problem found is returned.
    /// Allocation-free, O(count).
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), ExplicitScheduleError> {
        self.check_counted_header(OldStamps::Reject, limits).map_err(ExplicitScheduleError::Header)?;
        if self.count == 0 {
            return Err(ExplicitScheduleError::Empty);
        }
        for (index, s) in self.slots().iter().enumerate() {
            if s.center_index >= limits.center_count {
                return Err(ExplicitScheduleError::UnknownCenter { index, center_index: s.center_index });
            }
            if !s.k.is_finite() {
                return Err(ExplicitScheduleError::NonFinite { index, field: "k" });
            }
            if !limits.is_k_allowed(s.k) {
                return Err(ExplicitScheduleError::KOutOfRange { index });
            }
        }
        Ok(())
    }
}
