//! What a receiver knows about its rig, and the checks every `validate()` shares.

use crate::capacity::MAX_CENTERS;

/// Bounds a message is checked against. `Copy` and small: the solver thread
/// keeps one, refreshes `now_ns` before each `validate()`, and never
/// allocates.
///
/// Every bound is compared so that a NaN bound rejects (never accepts) input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidationLimits {
    /// Half-extents (x, y) in m of the plate area parts may occupy, centred
    /// on the plate origin: a part needs |x| ≤ `[0]` and |y| ≤ `[1]`.
    pub plate_half_extent_m: [f64; 2],
    /// The receiver's CLOCK_MONOTONIC time (ns) at validation.
    pub now_ns: u64,
    /// How far (ns) a stamp may lie ahead of `now_ns` before it is rejected
    /// as coming from the future (clock reads race between processes).
    pub max_future_skew_ns: u64,
    /// How old (ns before `now_ns`) a stamp may be before the message is
    /// rejected as stale; `u64::MAX` (the default) accepts any age.
    pub max_age_ns: u64,
    /// Number of configured rotation centers: valid indices are below it.
    pub center_count: u32,
    /// Bound on |k| of schedule slots; values above 1 are treated as 1.
    pub k_max: f64,
    /// Number of configured part classes: valid `class` codes are below it.
    pub part_class_count: u32,
    /// Number of configured friction classes: valid codes are below it.
    pub friction_class_count: u32,
}

impl ValidationLimits {
    /// Default for [`Self::max_future_skew_ns`]: 1 ms.
    pub const DEFAULT_MAX_FUTURE_SKEW_NS: u64 = 1_000_000;

    /// Limits for a plate of the given half-extents, checked at `now_ns`.
    /// Other fields: 1 ms skew, any age, [`MAX_CENTERS`] centers, k_max = 1 and any
    /// class code; set the fields to the rig's configuration.
    pub const fn new(plate_half_extent_m: [f64; 2], now_ns: u64) -> Self {
        Self {
            plate_half_extent_m,
            now_ns,
            max_future_skew_ns: Self::DEFAULT_MAX_FUTURE_SKEW_NS,
            max_age_ns: u64::MAX,
            center_count: MAX_CENTERS as u32,
            k_max: 1.0,
            part_class_count: u32::MAX,
            friction_class_count: u32::MAX,
        }
    }

    /// True if `stamp_ns` is later than `now_ns` plus the allowed skew.
    pub const fn is_from_future(&self, stamp_ns: u64) -> bool {
        stamp_ns > self.now_ns.saturating_add(self.max_future_skew_ns)
    }

    /// True if `stamp_ns` is more than `max_age_ns` before `now_ns`.
    pub const fn is_stale(&self, stamp_ns: u64) -> bool {
        self.now_ns.saturating_sub(stamp_ns) > self.max_age_ns
    }

    /// True if x lies on the plate (false for NaN input or bounds).
    pub fn is_on_plate_x(&self, x: f64) -> bool {
        x.abs() <= self.plate_half_extent_m[0]
    }

    /// True if y lies on the plate (false for NaN input or bounds).
    pub fn is_on_plate_y(&self, y: f64) -> bool {
        y.abs() <= self.plate_half_extent_m[1]
    }

    /// How far (m) a part's outline may reach from its position: the
    /// larger half-extent of the plate.
    pub fn max_part_extent(&self) -> f64 {
        let [x, y] = self.plate_half_extent_m;
        // NaN stays NaN (f64::max would drop it), so it rejects.
        if x.is_nan() || y.is_nan() { f64::NAN } else { x.max(y) }
    }

    /// True if |k| ≤ min(k_max, 1) (false for NaN k or a NaN k_max).
    pub fn is_k_allowed(&self, k: f64) -> bool {
        k.abs() <= self.k_max && k.abs() <= 1.0
    }
}

/// Number of entries of a payload to look at: `count` clamped to `capacity`.
pub(crate) fn clamped_len(count: u32, capacity: usize) -> usize {
    usize::try_from(count).map_or(capacity, |n| n.min(capacity))
}

/// True if `count` is within `capacity`.
pub(crate) fn count_fits(count: u32, capacity: usize) -> bool {
    usize::try_from(count).is_ok_and(|n| n <= capacity)
}

/// Integer flags on the wire are exactly 0 or 1.
pub(crate) const fn is_flag(value: u32) -> bool {
    value <= 1
}

/// The first of `fields` (name, value) that is not finite.
pub(crate) fn first_non_finite<const N: usize>(fields: [(&'static str, f64); N]) -> Option<&'static str> {
    fields.iter().find(|(_, v)| !v.is_finite()).map(|(name, _)| *name)
}
