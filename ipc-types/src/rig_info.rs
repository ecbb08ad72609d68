//! RigInfo: core → all, on `upm/rig_info`: the rig describing itself, so a
//! client needs no config file. Published once at start-up with history 1:
//! every subscriber, however late, receives it.

use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::capacity::{MAX_CENTERS, MAX_SLOTS};
use crate::header::{HeaderError, OldStamps};
use crate::health::detail_str;
use crate::validation::{ValidationLimits, first_non_finite};

/// Bytes of [`RigInfo::prefix`].
pub const RIG_PREFIX_BYTES: usize = 64;

/// One rotation center and the bound on |k| the core solves under there.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::RigCenter.v6"))]
pub struct RigCenter {
    /// Plate coordinates, m (a center may lie off the plate).
    pub x: f64,
    pub y: f64,
    /// min(k_max, the largest |k| the rig can play about this center).
    pub k_bound: f64,
}

const _: () = assert!(size_of::<RigCenter>() == 3 * 8);

impl RigCenter {
    pub const ZERO: Self = Self { x: 0.0, y: 0.0, k_bound: 0.0 };
}

/// Core → all: what a client needs to know about the rig (docs/protocol.md).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::RigInfo.v6"))]
pub struct RigInfo {
    pub protocol_version: u32,
    /// Number of used entries of `centers`.
    pub count: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when the core published it (at its start).
    pub stamp_ns: u64,
    /// The core's process id.
    pub core_pid: u32,
    /// 0: the paper's cycle, one slot per center; N > 0: cycles of N slots
    /// over the centers as candidates.
    pub cycle_slots: u32,
    /// `PartState.class` and `friction_class` codes must be below these;
    /// `u32::MAX`: any code.
    pub class_count: u32,
    pub friction_class_count: u32,
    /// Motor ticks per slot.
    pub slot_ticks: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
    /// One cycle: `count` slots (paper's cycle) or `cycle_slots` slots, of
    /// `slot_ticks` ticks each, ns.
    pub cycle_period_ns: u64,
    /// Motor tick rate, Hz.
    pub tick_hz: f64,
    /// The rate vision publishes PartStates at (`[vision] frame_hz`), Hz;
    /// 0 when the core was not told.
    pub vision_frame_hz: f64,
    /// μ·m·g of a part, N: the scale of every force.
    pub mu_m_g: f64,
    /// Parts must lie within |x| ≤ `[0]`, |y| ≤ `[1]`, m.
    pub plate_half_extent: [f64; 2],
    /// The configured bound on |k| (every center's `k_bound` is at most it).
    pub k_max: f64,
    /// The largest force one point part can be given anywhere on the
    /// plate, N (the formula is in docs/protocol.md), and where.
    pub max_part_force_n: f64,
    pub max_part_force_at: [f64; 2],
    /// With sparse cycles, no center closer than this to a constrained part
    /// is played, m.
    pub keep_out_m: f64,
    /// `Schedule.saturated` is 1 only if the residual exceeds
    /// `saturation_tolerance` × ‖request‖ + `saturation_floor`.
    pub saturation_tolerance: f64,
    pub saturation_floor: f64,
    /// Input older than these puts the plate in hold, ms.
    pub parts_max_age_ms: f64,
    pub request_max_age_ms: f64,
    /// A stamp further than this ahead of the core's clock is refused, ms.
    pub max_future_skew_ms: f64,
    /// The rig's iceoryx2 prefix, UTF-8, NUL-padded (cut to 64 bytes).
    pub prefix: [u8; RIG_PREFIX_BYTES],
    /// The rotation centers, in the order schedules index them.
    pub centers: [RigCenter; MAX_CENTERS],
}

const _: () = assert!(
    size_of::<RigInfo>()
        == 4 + 4
            + 2 * 8
            + 6 * 4
            + 8
            + 3 * 8
            + 2 * 8
            + 2 * 8
            + 2 * 8
            + 6 * 8
            + RIG_PREFIX_BYTES
            + MAX_CENTERS * size_of::<RigCenter>()
);

crate::counted_message::counted_message!(
    RigInfo,
    centers / centers_mut: [RigCenter; MAX_CENTERS],
    new {
        core_pid: 0, cycle_slots: 0, class_count: u32::MAX, friction_class_count: u32::MAX, slot_ticks: 0,
        reserved: 0, cycle_period_ns: 0, tick_hz: 0.0, vision_frame_hz: 0.0, mu_m_g: 0.0,
        plate_half_extent: [0.0; 2], k_max: 0.0, max_part_force_n: 0.0, max_part_force_at: [0.0; 2],
        keep_out_m: 0.0, saturation_tolerance: 0.0, saturation_floor: 0.0, parts_max_age_ms: 0.0,
        request_max_age_ms: 0.0, max_future_skew_ms: 0.0, prefix: [0; RIG_PREFIX_BYTES]
    }
);

/// Why a [`RigInfo`] is not a usable description. Indices refer to `centers`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigInfoError {
    /// Protocol version, count or stamp.
    Header(HeaderError),
    /// A float field is NaN or infinite.
    NonFinite {
        field: &'static str,
    },
    /// A field that must be positive is not.
    NotPositive {
        field: &'static str,
    },
    /// `k_max` is not in (0, 1).
    KMax,
    CycleSlots {
        slots: u32,
    },
    CenterNonFinite {
        index: usize,
    },
    /// A center's `k_bound` is not in (0, k_max].
    KBound {
        index: usize,
    },
}

impl fmt::Display for RigInfoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("rig_info", f),
            Self::NonFinite { field } => write!(f, "rig_info.{field} is not finite"),
            Self::NotPositive { field } => write!(f, "rig_info.{field} must be positive"),
            Self::KMax => f.write_str("rig_info.k_max must be in (0, 1)"),
            Self::CycleSlots { slots } => {
                write!(f, "rig_info.cycle_slots {slots} exceeds the capacity {MAX_SLOTS}")
            }
            Self::CenterNonFinite { index } => write!(f, "rig_info.centers[{index}] is not finite"),
            Self::KBound { index } => write!(f, "rig_info.centers[{index}].k_bound must be in (0, k_max]"),
        }
    }
}

impl core::error::Error for RigInfoError {}

impl RigInfo {
    /// Write `prefix` into [`Self::prefix`], cut to fit at a character
    /// boundary, NUL-padded.
    pub fn set_prefix(&mut self, prefix: &str) {
        self.prefix = [0; RIG_PREFIX_BYTES];
        let mut n = 0;
        for c in prefix.chars() {
            let len = c.len_utf8();
            if n + len > RIG_PREFIX_BYTES {
                break;
            }
            c.encode_utf8(&mut self.prefix[n..n + len]);
            n += len;
        }
    }

    /// The prefix, up to the first NUL (invalid UTF-8 is cut).
    pub fn prefix_str(&self) -> &str {
        detail_str(&self.prefix)
    }

    /// Check the whole message; the first problem found is returned.
    /// Allocation-free, O(count). Its stamp may be of any age.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), RigInfoError> {
        self.check_counted_header(OldStamps::Accept, limits).map_err(RigInfoError::Header)?;
        let [hx, hy] = self.plate_half_extent;
        let [ax, ay] = self.max_part_force_at;
        if let Some(field) = first_non_finite([
            ("tick_hz", self.tick_hz),
            ("vision_frame_hz", self.vision_frame_hz),
            ("mu_m_g", self.mu_m_g),
            ("plate_half_extent", hx),
            ("plate_half_extent", hy),
            ("k_max", self.k_max),
            ("max_part_force_n", self.max_part_force_n),
            ("max_part_force_at", ax),
            ("max_part_force_at", ay),
            ("keep_out_m", self.keep_out_m),
            ("saturation_tolerance", self.saturation_tolerance),
            ("saturation_floor", self.saturation_floor),
            ("parts_max_age_ms", self.parts_max_age_ms),
            ("request_max_age_ms", self.request_max_age_ms),
            ("max_future_skew_ms", self.max_future_skew_ms),
        ]) {
            return Err(RigInfoError::NonFinite { field });
        }
        for (field, v) in [
            ("tick_hz", self.tick_hz),
            ("mu_m_g", self.mu_m_g),
            ("plate_half_extent", hx.min(hy)),
            ("max_part_force_n", self.max_part_force_n),
            ("parts_max_age_ms", self.parts_max_age_ms),
            ("request_max_age_ms", self.request_max_age_ms),
        ] {
            if v <= 0.0 {
                return Err(RigInfoError::NotPositive { field });
            }
        }
        for (field, v) in [("slot_ticks", self.slot_ticks), ("count", self.count)] {
            if v == 0 {
                return Err(RigInfoError::NotPositive { field });
            }
        }
        if self.cycle_period_ns == 0 {
            return Err(RigInfoError::NotPositive { field: "cycle_period_ns" });
        }
        if !(self.k_max > 0.0 && self.k_max < 1.0) {
            return Err(RigInfoError::KMax);
        }
        if self.cycle_slots as usize > MAX_SLOTS {
            return Err(RigInfoError::CycleSlots { slots: self.cycle_slots });
        }
        for (index, c) in self.centers().iter().enumerate() {
            if first_non_finite([("x", c.x), ("y", c.y), ("k_bound", c.k_bound)]).is_some() {
                return Err(RigInfoError::CenterNonFinite { index });
            }
            if !(c.k_bound > 0.0 && c.k_bound <= self.k_max) {
                return Err(RigInfoError::KBound { index });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_prefix_is_cut_at_a_character_boundary() {
        let mut m = RigInfo::new();
        m.set_prefix("upm_run_42_");
        assert_eq!(m.prefix_str(), "upm_run_42_");
        m.set_prefix(&"é".repeat(40));
        assert_eq!(m.prefix_str().len(), 64);
        m.set_prefix(&format!("a{}", "é".repeat(40)));
        assert_eq!(m.prefix_str().len(), 63);
    }
}
