//! What a feed cell did in a run, as `metrics.json`'s `feed` object: from
//! its last `FeedStatus` and every pick, whether read from the simulator
//! (lock-step) or off `upm/feed` (a multi-process run).

use std::collections::BTreeMap;

use ipc_types::{FeedStatus, PickEvent, ValidationLimits, monotonic_now_ns};
use serde_json::{Value, json};

/// A feed cell at the end of a run.
#[derive(Debug, Clone)]
pub struct FeedOutcome {
    /// The cell's last status (its counters, stuck parts, collisions).
    pub last: FeedStatus,
    /// Every pick, oldest first.
    pub picks: Vec<PickEvent>,
    /// Picks the counters have that were never seen one by one (a reader
    /// that fell more than a message's worth of picks behind).
    pub picks_unseen: u64,
    /// Seconds the run lasted, on the cell's clock.
    pub seconds: f64,
}

impl FeedOutcome {
    /// The cell around `sim` now, `seconds` into the run.
    pub fn of(sim: &drivers::Simulator, seconds: f64) -> Option<Self> {
        let feed = drivers::feed::FeedCell::of(sim)?;
        let mut last = FeedStatus::new();
        feed.write_status(sim, &mut last);
        let picks: Vec<PickEvent> = (1..=last.picked).filter_map(|n| feed.pick_numbered(n)).collect();
        Some(Self { picks_unseen: last.picked - picks.len() as u64, last, picks, seconds })
    }

    /// Picks a minute after the first minute (None on a run of a minute or less).
    pub fn parts_per_minute(&self) -> Option<f64> {
        let after = self.picks.iter().filter(|p| p.time_s >= 60.0).count();
        (self.seconds > 60.0).then(|| after as f64 * 60.0 / (self.seconds - 60.0))
    }

    /// The p99 (nearest rank) of the picks' position error (mm) and angle error (°).
    pub fn error_p99(&self) -> (Option<f64>, Option<f64>) {
        let sorted = |f: fn(&PickEvent) -> f64| {
            let mut v: Vec<f64> = self.picks.iter().map(f).collect();
            v.sort_by(f64::total_cmp);
            upm_stats::percentile(&v, 0.99)
        };
        (sorted(|p| p.position_error_m * 1e3), sorted(|p| p.angle_error_rad.abs().to_degrees()))
    }

    /// The median time from a part's arrival to its pick (s).
    pub fn on_plate_median_s(&self) -> Option<f64> {
        let mut v: Vec<f64> = self.picks.iter().map(|p| p.on_plate_s).collect();
        upm_stats::median(&mut v)
    }

    pub fn to_json(&self) -> Value {
        let (pose_mm, angle_deg) = self.error_p99();
        let s = &self.last;
        let idle = 1.0 - s.robot_busy_s / self.seconds.max(f64::MIN_POSITIVE);
        json!({
            "arrived": s.arrived,
            "picked": s.picked,
            "parts_per_minute": self.parts_per_minute(),
            "pose_error_p99_mm": pose_mm,
            "angle_error_p99_deg": angle_deg,
            "robot_idle_fraction": idle.clamp(0.0, 1.0),
            "lost": s.lost,
            "collisions": s.collisions,
            "stuck": s.stuck,
            "stuck_after_s": s.stuck_after_s,
            "on_plate": s.on_plate,
            "arrivals_blocked": s.arrivals_blocked,
            "picks_unseen": self.picks_unseen,
            "on_plate_median_s": self.on_plate_median_s(),
        })
    }
}

/// A reader of `upm/feed`: keeps the newest valid status and every pick
/// by its number; counts what it refused.
#[derive(Debug, Clone, Default)]
pub struct FeedLog {
    pub last: Option<FeedStatus>,
    picks: BTreeMap<u64, PickEvent>,
    /// Messages that failed validation (each ignored).
    pub invalid: u64,
}

impl FeedLog {
    pub fn take(&mut self, m: &FeedStatus) {
        let limits = ValidationLimits::new([f64::INFINITY; 2], monotonic_now_ns());
        if m.validate(&limits).is_err() {
            self.invalid += 1;
            return;
        }
        for p in m.recent() {
            self.picks.entry(p.number).or_insert(*p);
        }
        if self.last.is_none_or(|l| m.seq > l.seq) {
            self.last = Some(*m);
        }
    }

    /// What the run came to (None if no status arrived).
    pub fn outcome(&self) -> Option<FeedOutcome> {
        let last = self.last?;
        let picks: Vec<PickEvent> = self.picks.values().copied().collect();
        Some(FeedOutcome {
            picks_unseen: last.picked.saturating_sub(picks.len() as u64),
            last,
            picks,
            seconds: last.time_s,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pick(number: u64, time_s: f64, mm: f64) -> PickEvent {
        PickEvent { number, time_s, position_error_m: mm * 1e-3, ..PickEvent::ZERO }
    }

    #[test]
    fn the_rate_counts_only_picks_after_the_first_minute() {
        let mut last = FeedStatus::new();
        (last.picked, last.robot_busy_s) = (4, 4.0);
        let o = FeedOutcome {
            last,
            picks: vec![pick(1, 10.0, 0.1), pick(2, 61.0, 0.2), pick(3, 90.0, 0.9), pick(4, 100.0, 0.3)],
            picks_unseen: 0,
            seconds: 120.0,
        };
        assert_eq!(o.parts_per_minute(), Some(3.0));
        // The p99 of four is the largest: 0.9 mm, through m and back.
        assert!(o.error_p99().0.is_some_and(|mm| (mm - 0.9).abs() < 1e-12));
        let v = o.to_json();
        assert_eq!(v["robot_idle_fraction"].as_f64(), Some(1.0 - 4.0 / 120.0));
        assert!(FeedOutcome { seconds: 60.0, ..o }.parts_per_minute().is_none());
    }

    #[test]
    fn the_log_keeps_each_pick_once_and_counts_what_it_missed_or_refused() {
        let mut log = FeedLog::default();
        let mut m = FeedStatus::new();
        (m.seq, m.picked, m.time_s) = (1, 2, 70.0);
        m.push_pick(pick(1, 61.0, 0.1));
        m.push_pick(pick(2, 62.0, 0.2));
        log.take(&m);
        log.take(&m);
        // Picks 3 and 4 were never seen one by one; 5 was.
        let mut later = FeedStatus::new();
        (later.seq, later.picked, later.time_s) = (9, 5, 120.0);
        later.push_pick(pick(5, 110.0, 0.3));
        log.take(&later);
        let mut bad = later;
        (bad.seq, bad.time_s) = (10, f64::NAN);
        log.take(&bad);
        let o = log.outcome().expect("a status");
        assert_eq!(o.picks.iter().map(|p| p.number).collect::<Vec<_>>(), [1, 2, 5]);
        assert_eq!((o.picks_unseen, o.seconds, log.invalid), (2, 120.0, 1));
        assert_eq!(o.parts_per_minute(), Some(3.0 * 60.0 / 60.0));
    }
}
