//! The camera loop: ground truth in, tracked PartStates out.

use std::time::Duration;

use iceoryx2::node::NodeWaitFailure;
use iceoryx2::prelude::*;
use ipc_types::discovery::CoreWatch;
use ipc_types::inbox_event::InboxNotifier;
use ipc_types::rig_node::rig_node;
use ipc_types::{PartState, PartStates, monotonic_now_ns, service_names};

use crate::{Camera, CameraParams, Track, Tracker, TrackerParams};

/// Turn a frame's tracks into the PartStates message.
pub fn part_states(tracks: &[Track], seq: u64, stamp_ns: u64, out: &mut PartStates) {
    out.clear();
    out.seq = seq;
    out.stamp_ns = stamp_ns;
    for t in tracks.iter().filter(|t| t.missed == 0) {
        // More tracks than capacity: the rest are not reported this frame.
        let _ = out.push(PartState::new(t.id, t.class, 0, t.pose, t.velocity));
    }
}

/// Run the camera on `prefix` until SIGINT/SIGTERM (or `duration`).
pub fn run(
    prefix: &str,
    camera: CameraParams,
    tracker: TrackerParams,
    duration: Option<Duration>,
) -> anyhow::Result<u64> {
    let mut cam = Camera::new(camera).map_err(anyhow::Error::msg)?;
    let mut tracker = Tracker::new(tracker);
    let node = rig_node(
        prefix,
        Some(ipc_types::discovery::VISION_NODE),
        SignalHandlingMode::HandleTerminationRequests,
    )?;
    let truth = ipc_types::ports::subscriber::<PartStates>(&node, service_names::SIM_GROUND_TRUTH)?;
    let publisher = ipc_types::ports::publisher::<PartStates>(&node, service_names::PART_STATES)?;
    let mut wake = InboxNotifier::new(&node)?;
    let period_ns = (1e9 / cam.params().frame_hz) as u64;
    let start = monotonic_now_ns();
    let end = duration.map(|d| start + d.as_nanos() as u64);
    let mut next_frame = start;
    let mut newest: Option<PartStates> = None;
    let mut last_frame_stamp: Option<u64> = None;
    let mut seq = 0;
    let mut msg = PartStates::new();
    let mut core = CoreWatch::new(prefix, Duration::from_secs(1));
    loop {
        if let Some(news) = core.poll() {
            eprintln!("upm-vision: {news}");
        }
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
            let dt = last_dt(&mut seq, frame.stamp_ns, &mut msg);
            tracker.update(&frame.detections, dt);
            part_states(tracker.tracks(), seq, frame.stamp_ns, &mut msg);
            publisher.send_copy(msg).map_err(|e| anyhow::anyhow!("publishing part states: {e:?}"))?;
            wake.notify();
        }
        if end.is_some_and(|e| now >= e) {
            return Ok(seq);
        }
        match node.wait(Duration::from_micros(500)) {
            Ok(()) => {}
            Err(NodeWaitFailure::Interrupt | NodeWaitFailure::TerminationRequest) => return Ok(seq),
        }
    }
}

/// Advance the sequence and return the time since the previous frame (s).
fn last_dt(seq: &mut u64, stamp_ns: u64, prev: &mut PartStates) -> f64 {
    *seq += 1;
    if *seq == 1 || prev.stamp_ns == 0 { 0.0 } else { stamp_ns.saturating_sub(prev.stamp_ns) as f64 / 1e9 }
}
