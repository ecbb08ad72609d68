//! Vision's ground-truth test double: the simulator's ground truth in,
//! through the simulated camera (noise, latency, dropped frames) and the
//! tracker, PartStates out.

use std::time::Duration;

use ipc_types::{PartStates, monotonic_now_ns, service_names};

use crate::outputs::Outputs;
use crate::{Camera, Tracker, VisionSection};

/// Run the camera on `prefix` until SIGINT/SIGTERM (or `duration`).
pub fn run(prefix: &str, params: &VisionSection, duration: Option<Duration>) -> anyhow::Result<u64> {
    let mut cam = Camera::new(params).map_err(anyhow::Error::msg)?;
    let mut tracker = Tracker::new(params);
    let mut out = Outputs::open(prefix)?;
    let truth = ipc_types::ports::subscriber::<PartStates>(out.node(), service_names::SIM_GROUND_TRUTH)?;
    let period_ns = (1e9 / params.frame_hz) as u64;
    let start = monotonic_now_ns();
    let end = duration.map(|d| start + d.as_nanos() as u64);
    let mut next_frame = start;
    let mut newest: Option<PartStates> = None;
    let mut last_frame_stamp: Option<u64> = None;
    let mut seq = 0;
    loop {
        while let Some(s) = truth.receive().map_err(|e| anyhow::anyhow!("receiving ground truth: {e:?}"))? {
            newest = Some(*s.payload());
        }
        let now = monotonic_now_ns();
        if now >= next_frame {
            next_frame += period_ns;
            if next_frame < now {
                next_frame = now + period_ns;
            }
            // No core yet (or a dead one): wait, never crash.
            if let Some(t) = &newest
                && last_frame_stamp != Some(t.stamp_ns)
            {
                cam.capture(t);
                last_frame_stamp = Some(t.stamp_ns);
            }
        }
        while let Some(frame) = cam.ready(now) {
            seq += 1;
            tracker.update(&frame.detections, out.dt(frame.stamp_ns));
            out.publish(tracker.tracks(), seq, frame.stamp_ns)?;
        }
        if end.is_some_and(|e| now >= e) || !out.wait(Duration::from_micros(500)) {
            return Ok(seq);
        }
    }
}
