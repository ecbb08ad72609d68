//! A stand-in for vision and planner: publishes PartStates and
//! ForceRequests for the paper's §3.1 parts at a fixed period. Used by the
//! benches and the multi-process tests to keep a core running.

use ipc_types::wake_event::{WakeEvent, WakeNotifier};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use iceoryx2::prelude::*;
use ipc_types::rig_node::rig_node;
use ipc_types::{ForceEntry, ForceRequest, PartState, PartStates, monotonic_now_ns, service_names};

/// The paper's §3.1 parts: (id, position, force).
pub const PAPER_PARTS: [(u32, [f64; 2], [f64; 2]); 2] =
    [(1, [0.5, 0.0], [0.01, 0.01]), (2, [-0.75, 0.25], [-0.01, 0.0])];

pub fn part_states(seq: u64, stamp_ns: u64, parts: &[(u32, [f64; 2], [f64; 2])]) -> PartStates {
    let mut m = PartStates::new();
    m.seq = seq;
    m.stamp_ns = stamp_ns;
    for &(id, p, _) in parts.iter().take(PartStates::CAPACITY) {
        let _ = m.push(PartState::new(id, 0, 0, [p[0], p[1], 0.0], [0.0; 3]));
    }
    m
}

pub fn request(seq: u64, stamp_ns: u64, parts: &[(u32, [f64; 2], [f64; 2])], scale: f64) -> ForceRequest {
    let mut m = ForceRequest::new();
    m.seq = seq;
    m.stamp_ns = stamp_ns;
    m.deadline_ns = stamp_ns + 1_000_000_000;
    for &(id, _, f) in parts.iter().take(ForceRequest::CAPACITY) {
        let _ = m.push(ForceEntry::force(id, [f[0] * scale, f[1] * scale]));
    }
    m
}

/// Publish the §3.1 inputs on `prefix` every `period` until `stop`.
pub fn feed(prefix: &str, period: Duration, stop: &AtomicBool) -> anyhow::Result<()> {
    let node = rig_node(prefix, None, SignalHandlingMode::Disabled)?;
    let parts = ipc_types::ports::publisher::<PartStates>(&node, service_names::PART_STATES)?;
    let requests = ipc_types::ports::publisher::<ForceRequest>(&node, service_names::FORCE_REQUEST)?;
    let mut wake = WakeNotifier::new(&node, WakeEvent::Inbox)?;
    let mut seq = 0;
    while !stop.load(Ordering::Relaxed) {
        seq += 1;
        let mut states = part_states(seq, 0, &PAPER_PARTS);
        // Stamped right before the send, as the raw reference is: building
        // the 4 KB message is not transport latency.
        let now = monotonic_now_ns();
        states.stamp_ns = now;
        parts.send_copy(states).map_err(|e| anyhow::anyhow!("send: {e:?}"))?;
        // Each message announced at once, as the vision and planner do.
        wake.notify();
        requests
            .send_copy(request(seq, now, &PAPER_PARTS, 1.0))
            .map_err(|e| anyhow::anyhow!("send: {e:?}"))?;
        wake.notify();
        std::thread::sleep(period);
    }
    Ok(())
}
