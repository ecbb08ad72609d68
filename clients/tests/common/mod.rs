//! Message builders and iceoryx2 isolation shared by the core tests.
#![allow(dead_code)]

use ipc_types::{ForceEntry, ForceRequest, PartState, PartStates};

/// The paper's §3.1 parts: (id, position, force).
pub const PAPER_PARTS: [(u32, [f64; 2], [f64; 2]); 2] =
    [(1, [0.5, 0.0], [0.01, 0.01]), (2, [-0.75, 0.25], [-0.01, 0.0])];

pub fn part_states(seq: u64, stamp_ns: u64, parts: &[(u32, [f64; 2], [f64; 2])]) -> PartStates {
    let mut m = PartStates::new();
    m.seq = seq;
    m.stamp_ns = stamp_ns;
    for &(id, p, _) in parts {
        m.push(PartState::new(id, 0, 0, [p[0], p[1], 0.0], [0.0; 3])).expect("capacity");
    }
    m
}

pub fn request(seq: u64, stamp_ns: u64, parts: &[(u32, [f64; 2], [f64; 2])], scale: f64) -> ForceRequest {
    let mut m = ForceRequest::new();
    m.seq = seq;
    m.stamp_ns = stamp_ns;
    m.deadline_ns = stamp_ns + 1_000_000_000;
    for &(id, _, f) in parts {
        m.push(ForceEntry::force(id, [f[0] * scale, f[1] * scale])).expect("capacity");
    }
    m
}

/// A service prefix no other test or rig uses.
pub fn unique_prefix(tag: &str) -> String {
    let nanos =
        std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.subsec_nanos());
    format!("upmt_{tag}_{}_{nanos}_", std::process::id())
}

/// Remove the per-prefix segment iceoryx2 leaves in /dev/shm.
pub fn remove_prefix(prefix: &str) {
    if let Ok(config) = ipc_types::ports::config_with_prefix(prefix) {
        // SAFETY: every node on this prefix belongs to this test and is gone.
        let _ = unsafe {
            iceoryx2::testing::remove_global_mgmt_segment::<iceoryx2::prelude::ipc::Service>(&config)
        };
    }
}

/// Publish PartStates and ForceRequests for the paper's §3.1 parts on
/// `prefix` every `period` until `stop` is set.
pub fn feed(prefix: &str, period: std::time::Duration, stop: &std::sync::atomic::AtomicBool) {
    use iceoryx2::prelude::*;
    use ipc_types::ports::open_pub_sub;
    use ipc_types::{ForceRequest, PartStates, monotonic_now_ns, service_names};
    let config = ipc_types::ports::config_with_prefix(prefix).expect("prefix");
    let node = NodeBuilder::new()
        .config(&config)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .expect("node");
    let parts = open_pub_sub::<PartStates>(&node, service_names::PART_STATES)
        .expect("service")
        .publisher_builder()
        .create()
        .expect("publisher");
    let requests = open_pub_sub::<ForceRequest>(&node, service_names::FORCE_REQUEST)
        .expect("service")
        .publisher_builder()
        .create()
        .expect("publisher");
    let mut seq = 0;
    while !stop.load(std::sync::atomic::Ordering::Relaxed) {
        seq += 1;
        let now = monotonic_now_ns();
        parts.send_copy(part_states(seq, now, &PAPER_PARTS)).expect("send");
        requests.send_copy(request(seq, now, &PAPER_PARTS, 1.0)).expect("send");
        std::thread::sleep(period);
    }
}
