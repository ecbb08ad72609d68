//! Vision's ground-truth test double inside one process, for the lock-step
//! loop: the simulated camera (the `[vision]` noise, dropped frames and
//! latency, seeded) and the tracker, exactly as the vision process of
//! `upm run` runs them, so a lock-step run sees what a real run sees and
//! stays bit-identical for a seed.

use ipc_types::PartStates;
use upm_vision::{Camera, Tracker, part_states};

use crate::config::Config;

#[derive(Debug)]
pub struct TruthSight {
    camera: Camera,
    tracker: Tracker,
    /// Frames published so far (the PartStates seq).
    seq: u64,
    last_stamp_ns: Option<u64>,
}

impl TruthSight {
    pub fn new(config: &Config) -> anyhow::Result<Self> {
        Ok(Self {
            camera: Camera::new(&config.vision).map_err(anyhow::Error::msg)?,
            tracker: Tracker::new(&config.vision),
            seq: 0,
            last_stamp_ns: None,
        })
    }

    /// Take one frame of `truth` (it may be dropped).
    pub fn capture(&mut self, truth: &PartStates) {
        self.camera.capture(truth);
    }

    /// When the next captured frame comes out of the camera.
    pub fn next_ready_ns(&self) -> Option<u64> {
        self.camera.next_ready_ns()
    }

    /// The next frame out of the camera by `now_ns`, tracked, into `out`
    /// (false: none is due).
    pub fn next(&mut self, now_ns: u64, out: &mut PartStates) -> bool {
        let Some(frame) = self.camera.ready(now_ns) else { return false };
        let dt = self.last_stamp_ns.map_or(0.0, |l| frame.stamp_ns.saturating_sub(l) as f64 / 1e9);
        self.last_stamp_ns = Some(frame.stamp_ns);
        self.tracker.update(&frame.detections, dt);
        self.seq += 1;
        part_states(self.tracker.tracks(), self.seq, frame.stamp_ns, out);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ipc_types::PartState;

    fn truth(stamp_ns: u64, x: f64) -> PartStates {
        let mut s = PartStates::new();
        s.stamp_ns = stamp_ns;
        s.push(PartState::new(7, 1, 0, [x, 0.1, 0.0], [0.0; 3])).expect("room for one part");
        s
    }

    #[test]
    fn frames_come_out_after_the_latency_with_noise_and_tracker_ids() {
        let mut config = Config::default();
        config.vision.latency_s = 0.01;
        config.vision.noise_m = 0.0005;
        let mut sight = TruthSight::new(&config).expect("sight");
        let mut out = PartStates::new();
        sight.capture(&truth(1_000_000_000, 0.2));
        assert_eq!(sight.next_ready_ns(), Some(1_010_000_000));
        assert!(!sight.next(1_009_999_999, &mut out), "out before its latency");
        assert!(sight.next(1_010_000_000, &mut out));
        assert_eq!((out.seq, out.stamp_ns, out.parts().len()), (1, 1_000_000_000, 1));
        let p = out.parts()[0];
        // The tracker's own id, the class kept, the position seen with noise.
        assert_eq!((p.id, p.class), (1, 1));
        assert!(p.x != 0.2 && (p.x - 0.2).abs() < 0.005, "x {}", p.x);
        assert!(!sight.next(2_000_000_000, &mut out), "one frame in, one out");
    }
}
