//! What `upm run` watches while the loop runs (the flight recording is
//! upm-recorder's): part trails from the simulator's ground truth, the
//! core's newest telemetry, a feed cell's status and picks, how many parts
//! vision sees, and how many schedules took longer to solve than a camera
//! frame lasts.

use std::collections::BTreeMap;

use iceoryx2::prelude::*;
use ipc_types::ports::Sub;
use ipc_types::rig_node::rig_node;
use ipc_types::{FeedStatus, PartStates, Schedule, Telemetry, service_names};
use serde::Serialize;

/// Positions of one part over the run.
#[derive(Debug, Clone, Default, Serialize)]
pub struct PartTrail {
    pub class: u32,
    /// (t, x, y, θ), t in seconds since the first sample.
    pub points: Vec<[f64; 4]>,
}

/// Every part's trail, by ground-truth id.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Trails {
    pub parts: BTreeMap<u32, PartTrail>,
}

/// Trails kept: a run of hours on a feed cell sees thousands of parts, and
/// the oldest-ended trail makes room for a new one, so memory stays flat.
pub const MAX_TRAILS: usize = 64;
/// Points kept per trail: a trail that reaches this is thinned to every
/// other point, so a part that stays for hours (one stuck at the fence)
/// keeps its whole path at a coarser step. With [`MAX_TRAILS`] this bounds
/// the trails at 4 MiB; a picture needs no more.
pub const MAX_TRAIL_POINTS: usize = 1 << 11;

impl Trails {
    pub fn duration(&self) -> f64 {
        self.parts.values().filter_map(|p| p.points.last()).map(|p| p[0]).fold(0.0, f64::max)
    }

    /// Part `id` (of `class`) at `point` = (t, x, y, θ). A new part beyond
    /// [`MAX_TRAILS`] takes the place of the trail that ended first.
    pub fn push(&mut self, id: u32, class: u32, point: [f64; 4]) {
        if !self.parts.contains_key(&id) && self.parts.len() >= MAX_TRAILS {
            let ended_first = self
                .parts
                .iter()
                .min_by(|a, b| {
                    let end = |t: &PartTrail| t.points.last().map_or(f64::NEG_INFINITY, |q| q[0]);
                    end(a.1).total_cmp(&end(b.1))
                })
                .map(|(&k, _)| k);
            if let Some(k) = ended_first {
                self.parts.remove(&k);
            }
        }
        let trail = self.parts.entry(id).or_default();
        trail.class = class;
        if trail.points.len() >= MAX_TRAIL_POINTS {
            let mut k = 0;
            trail.points.retain(|_| {
                k += 1;
                k % 2 == 1
            });
        }
        trail.points.push(point);
    }
}

#[derive(Debug)]
pub struct Observer {
    _node: Node<ipc::Service>,
    truth: Sub<PartStates>,
    telemetry: Sub<Telemetry>,
    schedules: Sub<Schedule>,
    /// Vision's part states, for how many parts it sees.
    parts: Sub<PartStates>,
    feed_status: Sub<FeedStatus>,
    /// A feed cell's newest status and every pick (empty without a cell).
    pub feed: crate::feed_metrics::FeedLog,
    /// Parts in vision's newest PartStates (None before the first).
    pub parts_seen: Option<usize>,
    pub trails: Trails,
    /// Schedules seen, and those whose solve took longer than a frame.
    pub schedules_seen: u64,
    pub frames_late: u64,
    frame_period_ns: u64,
    pub last_telemetry: Option<Telemetry>,
    first_stamp: Option<u64>,
    last_sample: u64,
    sample_ns: u64,
}

impl Observer {
    /// Record at most `sample_hz` trail points per second; a solve longer
    /// than 1/`frame_hz` makes its frame late.
    pub fn new(prefix: &str, sample_hz: f64, frame_hz: f64) -> anyhow::Result<Self> {
        let node = rig_node(prefix, None, SignalHandlingMode::Disabled)?;
        let truth = ipc_types::ports::subscriber::<PartStates>(&node, service_names::SIM_GROUND_TRUTH)?;
        let telemetry = ipc_types::ports::subscriber::<Telemetry>(&node, service_names::TELEMETRY)?;
        let schedules = ipc_types::ports::subscriber::<Schedule>(&node, service_names::SCHEDULE)?;
        let parts = ipc_types::ports::subscriber::<PartStates>(&node, service_names::PART_STATES)?;
        let feed_status = ipc_types::ports::subscriber::<FeedStatus>(&node, service_names::FEED)?;
        Ok(Self {
            _node: node,
            truth,
            telemetry,
            schedules,
            parts,
            feed_status,
            feed: crate::feed_metrics::FeedLog::default(),
            parts_seen: None,
            trails: Trails::default(),
            schedules_seen: 0,
            frames_late: 0,
            frame_period_ns: (1e9 / frame_hz.max(1e-3)) as u64,
            last_telemetry: None,
            first_stamp: None,
            last_sample: 0,
            sample_ns: (1e9 / sample_hz.max(1.0)) as u64,
        })
    }

    /// Take whatever arrived. Returns the seconds of ground truth seen.
    pub fn poll(&mut self) -> anyhow::Result<f64> {
        while let Some(s) = self.telemetry.receive().map_err(|e| anyhow::anyhow!("telemetry: {e:?}"))? {
            self.last_telemetry = Some(*s.payload());
        }
        while let Some(s) = self.schedules.receive().map_err(|e| anyhow::anyhow!("schedule: {e:?}"))? {
            self.schedules_seen += 1;
            self.frames_late += u64::from(s.payload().solve_time_ns > self.frame_period_ns);
        }
        while let Some(s) = self.parts.receive().map_err(|e| anyhow::anyhow!("part states: {e:?}"))? {
            self.parts_seen = Some(s.payload().parts().len());
        }
        while let Some(s) = self.feed_status.receive().map_err(|e| anyhow::anyhow!("feed: {e:?}"))? {
            self.feed.take(s.payload());
        }
        while let Some(s) = self.truth.receive().map_err(|e| anyhow::anyhow!("ground truth: {e:?}"))? {
            let m = s.payload();
            let first = *self.first_stamp.get_or_insert(m.stamp_ns);
            if m.stamp_ns < self.last_sample + self.sample_ns && self.last_sample != 0 {
                continue;
            }
            self.last_sample = m.stamp_ns;
            let t = m.stamp_ns.saturating_sub(first) as f64 / 1e9;
            for p in m.parts() {
                self.trails.push(p.id, p.class, [t, p.x, p.y, p.theta]);
            }
        }
        Ok(self.trails.duration())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_new_part_beyond_the_cap_replaces_the_trail_that_ended_first() {
        let mut t = Trails::default();
        for id in 0..MAX_TRAILS as u32 {
            t.push(id, 0, [f64::from(id), 0.0, 0.0, 0.0]);
        }
        // Part 0's trail goes on; part 1's ended first.
        t.push(0, 0, [1000.0, 0.0, 0.0, 0.0]);
        t.push(9999, 1, [1001.0, 0.0, 0.0, 0.0]);
        assert_eq!(t.parts.len(), MAX_TRAILS);
        assert!(t.parts.contains_key(&0) && t.parts.contains_key(&9999) && !t.parts.contains_key(&1));
        assert_eq!(t.parts[&0].points.len(), 2);
    }

    #[test]
    fn a_trail_at_its_cap_is_thinned_and_keeps_its_start_and_newest_point() {
        let mut t = Trails::default();
        for i in 0..=MAX_TRAIL_POINTS {
            t.push(7, 0, [i as f64, 0.0, 0.0, 0.0]);
        }
        let points = &t.parts[&7].points;
        assert_eq!(points.len(), MAX_TRAIL_POINTS / 2 + 1);
        assert_eq!((points[0][0], points[1][0]), (0.0, 2.0));
        assert_eq!(points.last().map(|p| p[0]), Some(MAX_TRAIL_POINTS as f64));
    }
}
