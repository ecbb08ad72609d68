//! Schedule: core → all, the closed plate motion the core plays next.

use crate::header::{HeaderError, OldStamps};
use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::capacity::{MAX_CENTERS, MAX_SLOTS};
use crate::validation::{ValidationLimits, count_fits, first_non_finite, is_flag};

/// One slot in play order: rotation about center `center_index` at (x, y)
/// (m, plate coordinates; centers may lie off the plate) with intensity k.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::ScheduleSlot.v6"))]
pub struct ScheduleSlot {
    /// Index into the rig's configured centers.
    pub center_index: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
    pub x: f64,
    pub y: f64,
    pub k: f64,
}

const _: () = assert!(size_of::<ScheduleSlot>() == 4 + 4 + 3 * 8);

impl ScheduleSlot {
    pub const ZERO: Self = Self::new(0, [0.0; 2], 0.0);

    pub const fn new(center_index: u32, center: [f64; 2], k: f64) -> Self {
        Self { center_index, reserved: 0, x: center[0], y: center[1], k }
    }
}

/// Core → all: the schedule the solver produced (or the planner's explicit
/// one), with the solver's diagnostics.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::Schedule.v6"))]
pub struct Schedule {
    pub protocol_version: u32,
    /// Number of used entries of `slots`.
    pub count: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when the schedule was published.
    pub stamp_ns: u64,
    /// Motor cycle from which the schedule is played.
    pub cycle: u64,
    /// Wall time of the solve (ns); 0 for an explicit schedule.
    pub solve_time_ns: u64,
    /// `seq` and `stamp_ns` of the part states the schedule was solved
    /// against (the newest the core had accepted); 0 for an explicit
    /// schedule. With `seq` (the request's) they name the whole input.
    pub parts_seq: u64,
    pub parts_stamp_ns: u64,
    /// `stamp_ns` of the request (or explicit schedule) it answers.
    pub request_stamp_ns: u64,
    /// ‖A·K − b‖ over the request's rows: force rows in N, curl rows in
    /// N/m, one Euclidean norm over both; finite, ≥ 0.
    pub residual: f64,
    /// Estimated 2-norm condition number of A; ≥ 0, +∞ when rank-deficient,
    /// 0 when not estimated (a frame warm-started from the last frame's
    /// active bounds, and a sparse cycle, do not factor A).
    pub condition: f64,
    /// Numerical rank of A; 0 when not estimated (as `condition`).
    pub rank: u32,
    /// 1 when a bound on |k| keeps the request from being met: a bound is
    /// active and `residual` exceeds the saturation tolerance (relative
    /// 1e-3 of the request's norm, `RigInfo::saturation_tolerance`), else 0.
    pub saturated: u32,
    /// Centers whose |k| is at their bound (k_max, or the center's playable
    /// bound), whether or not the request is met; 0 for an explicit schedule.
    pub at_bound: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
    /// The slots in play order. With sparse cycles (`motion.cycle_slots`)
    /// a center may fill several consecutive slots.
    pub slots: [ScheduleSlot; MAX_SLOTS],
}

const _: () = assert!(
    size_of::<Schedule>() == 4 + 4 + 7 * 8 + 2 * 8 + 4 + 4 + 4 + 4 + MAX_SLOTS * size_of::<ScheduleSlot>()
);

/// Why a [`Schedule`] was rejected. Indices refer to `slots`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScheduleError {
    /// Protocol version, count or stamp.
    Header(HeaderError),

    /// `residual` is NaN, infinite or negative.
    InvalidResidual,
    /// `condition` is NaN or negative.
    InvalidCondition,
    RankExceedsCapacity {
        rank: u32,
    },
    /// `at_bound` above the number of centers a rig can have.
    AtBoundExceedsCapacity {
        at_bound: u32,
    },
    NotAFlag {
        field: &'static str,
        value: u32,
    },
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

impl fmt::Display for ScheduleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("schedule", f),
            Self::InvalidResidual => write!(f, "schedule.residual is not a finite number ≥ 0"),
            Self::InvalidCondition => write!(f, "schedule.condition is NaN or negative"),
            Self::RankExceedsCapacity { rank } => {
                write!(f, "schedule.rank {rank} exceeds the capacity {MAX_SLOTS}")
            }
            Self::AtBoundExceedsCapacity { at_bound } => {
                write!(f, "schedule.at_bound {at_bound} exceeds the capacity {MAX_CENTERS}")
            }
            Self::NotAFlag { field, value } => write!(f, "schedule.{field} is {value}, expected 0 or 1"),
            Self::UnknownCenter { index, center_index } => {
                write!(f, "schedule.slots[{index}].center_index {center_index} is not a configured center")
            }
            Self::NonFinite { index, field } => write!(f, "schedule.slots[{index}].{field} is not finite"),
            Self::KOutOfRange { index } => write!(f, "schedule.slots[{index}].k exceeds k_max"),
        }
    }
}

impl core::error::Error for ScheduleError {}

crate::counted_message::counted_message!(
    Schedule,
    slots / slots_mut: [ScheduleSlot; MAX_SLOTS],
    new { cycle: 0, solve_time_ns: 0, parts_seq: 0, parts_stamp_ns: 0, request_stamp_ns: 0, residual: 0.0, condition: 1.0, rank: 0, saturated: 0, at_bound: 0, reserved: 0 }
);

impl Schedule {
    /// True only if `saturated` is exactly 1.
    pub const fn is_saturated(&self) -> bool {
        self.saturated == 1
    }

    /// Check the whole message; the first problem found is returned.
    /// Allocation-free, O(count).
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), ScheduleError> {
        self.check_counted_header(OldStamps::Accept, limits).map_err(ScheduleError::Header)?;
        if !(self.residual.is_finite() && self.residual >= 0.0) {
            return Err(ScheduleError::InvalidResidual);
        }
        if self.condition.is_nan() || self.condition < 0.0 {
            return Err(ScheduleError::InvalidCondition);
        }
        if !count_fits(self.rank, MAX_SLOTS) {
            return Err(ScheduleError::RankExceedsCapacity { rank: self.rank });
        }
        if !count_fits(self.at_bound, MAX_CENTERS) {
            return Err(ScheduleError::AtBoundExceedsCapacity { at_bound: self.at_bound });
        }
        if !is_flag(self.saturated) {
            return Err(ScheduleError::NotAFlag { field: "saturated", value: self.saturated });
        }
        for (index, s) in self.slots().iter().enumerate() {
            if s.center_index >= limits.center_count {
                return Err(ScheduleError::UnknownCenter { index, center_index: s.center_index });
            }
            if let Some(field) = first_non_finite([("x", s.x), ("y", s.y), ("k", s.k)]) {
                return Err(ScheduleError::NonFinite { index, field });
            }
            if !limits.is_k_allowed(s.k) {
                return Err(ScheduleError::KOutOfRange { index });
            }
        }
        Ok(())
    }
}
