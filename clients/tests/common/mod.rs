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
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.subsec_nanos());
    format!("upmt_{tag}_{}_{nanos}_", std::process::id())
}

/// Remove the per-prefix segment iceoryx2 leaves in /dev/shm.
pub fn remove_prefix(prefix: &str) {
    if let Ok(config) = ipc_types::ports::config_with_prefix(prefix) {
        // SAFETY: every node on this prefix belongs to this test and is gone.
        let _ = unsafe { iceoryx2::testing::remove_global_mgmt_segment::<iceoryx2::prelude::ipc::Service>(&config) };
    }
}
