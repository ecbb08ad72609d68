//! What a feed cell did in a run, as `metrics.json`'s `feed` object.

use drivers::feed::{FeedCounts, PickRecord};
use serde_json::{Value, json};

/// A part on the plate longer than this is stuck.
pub const STUCK_S: f64 = 120.0;

/// A feed cell at the end of a run.
#[derive(Debug, Clone)]
pub struct FeedOutcome {
    pub counts: FeedCounts,
    pub picks: Vec<PickRecord>,
    /// Parts on the plate longer than [`STUCK_S`] at the end.
    pub stuck: u32,
    /// Part–part impacts the simulator counted.
    pub collisions: u64,
    /// Simulated seconds the run lasted.
    pub seconds: f64,
    /// The robot's cycle per part (s).
    pub pick_s: f64,
}

impl FeedOutcome {
    /// The cell around `sim` now, `seconds` into the run.
    pub fn of(sim: &drivers::Simulator, seconds: f64) -> Option<Self> {
        let feed = drivers::feed::FeedCell::of(sim)?;
        Some(Self {
            counts: feed.counts(),
            picks: feed.picks(),
            stuck: feed.on_plate_longer_than(sim.time(), STUCK_S),
            collisions: sim.counters().collisions,
            seconds,
            pick_s: feed.recipe().robot.pick_s,
        })
    }

    /// Picks a minute after the first minute (None on a run of a minute or less).
    pub fn parts_per_minute(&self) -> Option<f64> {
        let after = self.picks.iter().filter(|p| p.t >= 60.0).count();
        (self.seconds > 60.0).then(|| after as f64 * 60.0 / (self.seconds - 60.0))
    }

    /// The p99 (nearest rank) of the picks' position error (mm) and angle error (°).
    pub fn error_p99(&self) -> (Option<f64>, Option<f64>) {
        let sorted = |f: fn(&PickRecord) -> f64| {
            let mut v: Vec<f64> = self.picks.iter().map(f).collect();
            v.sort_by(f64::total_cmp);
            upm_stats::percentile(&v, 0.99)
        };
        (sorted(|p| p.position_error * 1e3), sorted(|p| p.angle_error.abs().to_degrees()))
    }

    pub fn to_json(&self) -> Value {
        let (pose_mm, angle_deg) = self.error_p99();
        let busy = self.counts.picked as f64 * self.pick_s;
        json!({
            "arrived": self.counts.arrived,
            "picked": self.counts.picked,
            "parts_per_minute": self.parts_per_minute(),
            "pose_error_p99_mm": pose_mm,
            "angle_error_p99_deg": angle_deg,
            "robot_idle_fraction": (1.0 - busy / self.seconds.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0),
            "lost": self.counts.lost,
            "collisions": self.collisions,
            "stuck": self.stuck,
            "on_plate": self.counts.on_plate,
            "arrivals_blocked": self.counts.arrivals_blocked,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_counts_only_picks_after_the_first_minute() {
        let pick = |t: f64, mm: f64| PickRecord { t, position_error: mm * 1e-3, ..PickRecord::default() };
        let o = FeedOutcome {
            counts: FeedCounts { picked: 4, ..FeedCounts::default() },
            picks: vec![pick(10.0, 0.1), pick(61.0, 0.2), pick(90.0, 0.9), pick(100.0, 0.3)],
            stuck: 0,
            collisions: 0,
            seconds: 120.0,
            pick_s: 1.0,
        };
        assert_eq!(o.parts_per_minute(), Some(3.0));
        // The p99 of four is the largest: 0.9 mm, through m and back.
        assert!(o.error_p99().0.is_some_and(|mm| (mm - 0.9).abs() < 1e-12));
        let v = o.to_json();
        assert_eq!(v["robot_idle_fraction"].as_f64(), Some(1.0 - 4.0 / 120.0));
        assert!(FeedOutcome { seconds: 60.0, ..o }.parts_per_minute().is_none());
    }
}
