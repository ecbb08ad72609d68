//! FeedStatus: core → all, on `upm/feed`: what a feed cell is doing — its
//! counters, each pick pose's state and the latest picks. Published at the
//! camera's rate while the core runs a cell (today: the simulator's); a
//! subscriber that keeps every pick reads `recent` by `number`, so a missed
//! message loses no pick as long as fewer than [`FEED_RECENT_PICKS`] picks
//! happen between two it reads.

use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::header::{HeaderError, OldStamps};
use crate::validation::{ValidationLimits, clamped_len, first_non_finite};

/// Most pick poses one message describes.
pub const MAX_PICK_POSES: usize = 16;
/// Picks one message carries, the newest last.
pub const FEED_RECENT_PICKS: usize = 16;

/// One pick pose of the recipe, and whether a part waits there.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::PickPoseState.v6"))]
pub struct PickPoseState {
    /// The recipe class this pose takes.
    pub class: u32,
    /// The part lying at the pose within tolerance; 0: none.
    pub part_id: u32,
    /// 1: that part has lain there for the settle time, with no other part
    /// in the gripper's clearance: the robot may take it. 0: not ready.
    pub ready: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
    /// The pose, plate coordinates: m, m, rad.
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

const _: () = assert!(size_of::<PickPoseState>() == 4 * 4 + 3 * 8);

impl PickPoseState {
    pub const ZERO: Self = Self { class: 0, part_id: 0, ready: 0, reserved: 0, x: 0.0, y: 0.0, theta: 0.0 };
}

/// One pick, at the instant the robot closed on the part.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::PickEvent.v6"))]
pub struct PickEvent {
    /// 1 for the cell's first pick, then one more for each.
    pub number: u64,
    pub part_id: u32,
    pub class: u32,
    /// Index of the pick pose (`FeedStatus::poses`).
    pub pose: u32,
    /// Unused, keep 0.
    pub reserved: u32,
    /// When, s since the cell started.
    pub time_s: f64,
    /// Distance of the part from the pose, m, and its angle from the pose's
    /// θ modulo the outline's symmetry, rad, against the truth.
    pub position_error_m: f64,
    pub angle_error_rad: f64,
    /// From the part's arrival to its pick, s.
    pub on_plate_s: f64,
}

const _: () = assert!(size_of::<PickEvent>() == 8 + 4 * 4 + 4 * 8);

impl PickEvent {
    pub const ZERO: Self = Self {
        number: 0,
        part_id: 0,
        class: 0,
        pose: 0,
        reserved: 0,
        time_s: 0.0,
        position_error_m: 0.0,
        angle_error_rad: 0.0,
        on_plate_s: 0.0,
    };
}

/// Core → all: a feed cell's state (docs/protocol.md). `count` is the
/// number of used `poses`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::FeedStatus.v6"))]
pub struct FeedStatus {
    pub protocol_version: u32,
    pub count: u32,
    pub seq: u64,
    pub stamp_ns: u64,
    /// Since the cell started: parts that landed, that the robot took, that
    /// left the plate any other way, and arrivals that found no free spot
    /// at once (each waits and tries again).
    pub arrived: u64,
    pub picked: u64,
    pub lost: u64,
    pub arrivals_blocked: u64,
    /// Parts on the plate now, and of them those there longer than
    /// `stuck_after_s`.
    pub on_plate: u32,
    pub stuck: u32,
    /// Used entries of `recent`.
    pub recent_count: u32,
    /// Part–part impacts since the cell started (where the cell can see
    /// them: the simulator counts them; 0 otherwise).
    pub collisions: u32,
    /// The cell's clock, s since it started; of it, the robot's time spent
    /// picking, s.
    pub time_s: f64,
    pub robot_busy_s: f64,
    pub stuck_after_s: f64,
    /// The latest picks, oldest first.
    pub recent: [PickEvent; FEED_RECENT_PICKS],
    pub poses: [PickPoseState; MAX_PICK_POSES],
}

const _: () = assert!(
    size_of::<FeedStatus>()
        == 4 + 4
            + 2 * 8
            + 4 * 8
            + 4 * 4
            + 3 * 8
            + FEED_RECENT_PICKS * size_of::<PickEvent>()
            + MAX_PICK_POSES * size_of::<PickPoseState>()
);

crate::counted_message::counted_message!(
    FeedStatus,
    poses / poses_mut: [PickPoseState; MAX_PICK_POSES],
    new {
        arrived: 0, picked: 0, lost: 0, arrivals_blocked: 0, on_plate: 0, stuck: 0, recent_count: 0,
        collisions: 0, time_s: 0.0, robot_busy_s: 0.0, stuck_after_s: 0.0,
        recent: [PickEvent::ZERO; FEED_RECENT_PICKS]
    }
);

/// Why a [`FeedStatus`] is not a usable report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeedStatusError {
    /// Protocol version, count or stamp.
    Header(HeaderError),
    /// `recent_count` exceeds the capacity.
    RecentCount { count: u32 },
    /// A float field is NaN or infinite (`recent[i]` and `poses[i]` are
    /// named by their field).
    NonFinite { field: &'static str },
}

impl fmt::Display for FeedStatusError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("feed_status", f),
            Self::RecentCount { count } => {
                write!(f, "feed_status.recent_count {count} exceeds the capacity {FEED_RECENT_PICKS}")
            }
            Self::NonFinite { field } => write!(f, "feed_status.{field} is not finite"),
        }
    }
}

impl core::error::Error for FeedStatusError {}

impl FeedStatus {
    /// The latest picks, oldest first; a corrupt count is clamped.
    pub fn recent(&self) -> &[PickEvent] {
        &self.recent[..clamped_len(self.recent_count, FEED_RECENT_PICKS)]
    }

    /// Append a pick, dropping the oldest when full. Allocation-free.
    pub fn push_pick(&mut self, pick: PickEvent) {
        let n = clamped_len(self.recent_count, FEED_RECENT_PICKS);
        if n == FEED_RECENT_PICKS {
            self.recent.copy_within(1.., 0);
            self.recent[FEED_RECENT_PICKS - 1] = pick;
        } else {
            self.recent[n] = pick;
            self.recent_count = n as u32 + 1;
        }
    }

    /// Check the whole message; the first problem found is returned.
    /// Allocation-free. Its stamp may be of any age.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), FeedStatusError> {
        self.check_counted_header(OldStamps::Accept, limits).map_err(FeedStatusError::Header)?;
        if self.recent_count as usize > FEED_RECENT_PICKS {
            return Err(FeedStatusError::RecentCount { count: self.recent_count });
        }
        let top = first_non_finite([
            ("time_s", self.time_s),
            ("robot_busy_s", self.robot_busy_s),
            ("stuck_after_s", self.stuck_after_s),
        ]);
        let picks = self.recent().iter().find_map(|p| {
            first_non_finite([
                ("recent.time_s", p.time_s),
                ("recent.position_error_m", p.position_error_m),
                ("recent.angle_error_rad", p.angle_error_rad),
                ("recent.on_plate_s", p.on_plate_s),
            ])
        });
        let poses = self
            .poses()
            .iter()
            .find_map(|p| first_non_finite([("poses.x", p.x), ("poses.y", p.y), ("poses.theta", p.theta)]));
        match top.or(picks).or(poses) {
            Some(field) => Err(FeedStatusError::NonFinite { field }),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recent_keeps_the_newest_picks_in_order() {
        let mut m = FeedStatus::new();
        for n in 1..=FEED_RECENT_PICKS as u64 + 3 {
            m.push_pick(PickEvent { number: n, ..PickEvent::ZERO });
        }
        let numbers: Vec<u64> = m.recent().iter().map(|p| p.number).collect();
        assert_eq!(numbers.first(), Some(&4));
        assert_eq!(numbers.last(), Some(&(FEED_RECENT_PICKS as u64 + 3)));
        assert_eq!(numbers.len(), FEED_RECENT_PICKS);
    }

    #[test]
    fn a_corrupt_count_or_a_nan_is_named() {
        let limits = ValidationLimits::new([1.0, 1.0], 10);
        let mut m = FeedStatus::new();
        m.stamp_ns = 1;
        assert_eq!(m.validate(&limits), Ok(()));
        m.recent_count = 99;
        assert_eq!(m.recent().len(), FEED_RECENT_PICKS);
        assert!(m.validate(&limits).is_err_and(|e| e.to_string().contains("recent_count 99")));
        m.recent_count = 1;
        m.recent[0].angle_error_rad = f64::NAN;
        let e = m.validate(&limits).expect_err("NaN");
        assert_eq!(e.to_string(), "feed_status.recent.angle_error_rad is not finite");
    }
}
