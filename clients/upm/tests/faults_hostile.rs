//! Issue 7 (first part): a rogue process publishes hostile PartStates and
//! ForceRequests to a running upm-core. Every message is rejected and
//! counted (visible in telemetry / `upm status`), and the core keeps running.

mod common;

use std::process::Command;
use std::time::{Duration, Instant};

use ipc_types::{
    ForceEntry, ForceRequest, PROTOCOL_VERSION, PartState, PartStates, monotonic_now_ns, service_names,
};
use upm_commands::status::read_telemetry;
use upm_test_harness::Running;

#[test]
fn hostile_messages_are_rejected_counted_and_the_core_survives() {
    let prefix = common::unique_prefix("hostile");
    let core = Running(
        Command::new(common::core_exe())
            .args(["--prefix", &prefix, "--duration", "60"])
            .spawn()
            .expect("core"),
    );
    let start = Instant::now();
    while read_telemetry(&prefix, Duration::from_millis(500)).is_err() {
        assert!(start.elapsed() < Duration::from_secs(20), "core did not come up");
    }
    let node = common::plain_node(&prefix);
    let parts =
        ipc_types::ports::publisher::<PartStates>(&node, service_names::PART_STATES).expect("publisher");
    let requests =
        ipc_types::ports::publisher::<ForceRequest>(&node, service_names::FORCE_REQUEST).expect("publisher");
    std::thread::sleep(Duration::from_millis(200));

    let now = monotonic_now_ns();
    let good = common::part_states(1, now, &common::PAPER_PARTS);
    let mut hostile_parts = Vec::new();
    let mut m = good;
    m.parts_mut()[0].x = f64::NAN;
    hostile_parts.push(m);
    let mut m = good;
    m.parts_mut()[1].vy = f64::INFINITY;
    hostile_parts.push(m);
    let mut m = good;
    m.count = u32::MAX;
    hostile_parts.push(m);
    let mut m = good;
    m.protocol_version = PROTOCOL_VERSION + 7;
    hostile_parts.push(m);
    let mut m = good;
    m.parts_mut()[1].id = m.parts()[0].id;
    hostile_parts.push(m);
    let mut m = good;
    m.parts_mut()[0] = PartState::new(1, 0, 0, [50.0, 0.0, 0.0], [0.0; 3]);
    hostile_parts.push(m);
    let mut m = good;
    m.stamp_ns = now + 60_000_000_000;
    hostile_parts.push(m);
    let mut hostile_requests = Vec::new();
    let mut r = common::request(1, now, &common::PAPER_PARTS, 1.0);
    r.entries_mut()[0].fx = f64::NAN;
    hostile_requests.push(r);
    let mut r = common::request(1, now, &common::PAPER_PARTS, 1.0);
    r.count = 100_000;
    hostile_requests.push(r);
    let mut r = common::request(1, now, &common::PAPER_PARTS, 1.0);
    r.entries_mut()[1] = ForceEntry { force_flag: 7, ..r.entries()[1] };
    hostile_requests.push(r);
    let mut r = common::request(1, now, &common::PAPER_PARTS, 1.0);
    r.protocol_version = 0;
    hostile_requests.push(r);
    // Space them out so the subscriber's bounded buffer never overflows.
    for m in &hostile_parts {
        parts.send_copy(*m).expect("send");
        std::thread::sleep(Duration::from_millis(20));
    }
    for r in &hostile_requests {
        requests.send_copy(*r).expect("send");
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut t = read_telemetry(&prefix, Duration::from_secs(2)).expect("telemetry");
    let start = Instant::now();
    while (t.counters.rejected_parts as usize) < hostile_parts.len()
        && start.elapsed() < Duration::from_secs(5)
    {
        std::thread::sleep(Duration::from_millis(100));
        t = read_telemetry(&prefix, Duration::from_secs(2)).expect("telemetry");
    }
    drop(core);
    // The ports and node first: they hold the prefix's files.
    drop((parts, requests, node));
    common::remove_prefix(&prefix);
    assert_eq!(t.counters.rejected_parts, hostile_parts.len() as u64);
    // Every request is rejected: invalid, or (the last) without valid part states.
    assert_eq!(t.counters.rejected_requests, hostile_requests.len() as u64);
    assert_ne!(t.core_state(), Some(ipc_types::CoreState::Fault));
    assert_eq!([t.plate_x, t.plate_y, t.plate_theta], [0.0; 3], "the plate never moved");
    assert_eq!(t.counters.rt_thread_allocations, 0);
}
