//! upm-core as a separate process: a test publisher feeds PartStates and
//! ForceRequests over iceoryx2, Schedules come back, `upm status` reports
//! the state, stale input holds, a second core on the same prefix is
//! refused, and SIGINT stops it cleanly with histograms written.

mod common;

use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use ipc_types::{CoreState, Schedule, service_names};
use upm_cli::status::read_telemetry;

struct Core(Child);

impl Drop for Core {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn wait_state(prefix: &str, want: CoreState, within: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < within {
        if let Ok(t) = read_telemetry(prefix, Duration::from_secs(1))
            && t.core_state() == Some(want)
        {
            return true;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    false
}

fn start_feeder(prefix: &str) -> (Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    let stop = Arc::new(AtomicBool::new(false));
    let (p, s) = (prefix.to_owned(), stop.clone());
    (stop, std::thread::spawn(move || common::feed(&p, Duration::from_millis(10), &s)))
}

#[test]
fn core_process_round_trip_hold_single_instance_and_clean_stop() {
    let prefix = common::unique_prefix("mp");
    let hgrm = std::env::temp_dir().join(format!("{prefix}hgrm"));
    let core = Command::new(common::core_exe())
        .args(["--prefix", &prefix, "--duration", "120", "--histograms"])
        .arg(&hgrm)
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn upm-core");
    let mut core = Core(core);
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        assert!(wait_state(&prefix, CoreState::Idle, Duration::from_secs(20)), "core came up idle");

        // Subscribe to schedules, then feed.
        let node = common::plain_node(&prefix);
        let schedules =
            ipc_types::ports::subscriber::<Schedule>(&node, service_names::SCHEDULE).expect("subscriber");
        let (stop, feeder) = start_feeder(&prefix);
        let start = Instant::now();
        let mut got = None;
        while got.is_none() && start.elapsed() < Duration::from_secs(20) {
            if let Some(s) = schedules.receive().expect("receive") {
                got = Some(*s.payload());
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        let s = got.expect("a schedule came back");
        let mut k = [0.0f64; 4];
        for slot in s.slots() {
            k[slot.center_index as usize] = slot.k;
        }
        for (got, want) in k.iter().zip([0.584f64, -0.389, 0.480, -0.0946]) {
            assert!((got - want).abs() < 0.006, "k {k:?}");
        }
        assert!(wait_state(&prefix, CoreState::Running, Duration::from_secs(10)), "running");

        // `upm status --json` through the real binary.
        let out = Command::new(env!("CARGO_BIN_EXE_upm"))
            .args(["status", "--json", "--prefix", &prefix])
            .output()
            .expect("upm status");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        assert_eq!(v["state"], "running");
        assert!(v["latency_us"]["motor_wakeup"]["p99"].as_f64().is_some());

        // A second core on the same prefix refuses to start.
        let second = Command::new(common::core_exe())
            .args(["--prefix", &prefix, "--duration", "1"])
            .output()
            .expect("second core");
        assert!(!second.status.success());
        let err = String::from_utf8_lossy(&second.stderr);
        assert!(err.contains("already running"), "{err}");

        // Stale input: hold; fresh input: running again.
        stop.store(true, Ordering::Relaxed);
        feeder.join().expect("feeder");
        assert!(wait_state(&prefix, CoreState::Hold, Duration::from_secs(5)), "held on stale input");
        let (stop, feeder) = start_feeder(&prefix);
        assert!(wait_state(&prefix, CoreState::Running, Duration::from_secs(5)), "resumed");
        stop.store(true, Ordering::Relaxed);
        feeder.join().expect("feeder");
    }));

    // SIGINT: clean stop, histograms written.
    // SAFETY: plain kill(2) on our own child.
    unsafe { libc::kill(core.0.id() as libc::pid_t, libc::SIGINT) };
    let start = Instant::now();
    let status = loop {
        if let Some(s) = core.0.try_wait().expect("wait") {
            break Some(s);
        }
        if start.elapsed() > Duration::from_secs(20) {
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    if let Some(mut e) = core.0.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    common::remove_prefix(&prefix);
    if let Err(p) = result {
        std::panic::resume_unwind(p);
    }
    let status = status.expect("core exited after SIGINT");
    assert!(status.success(), "core exit {status:?}: {stderr}");
    assert!(stderr.contains("stopped cleanly"), "{stderr}");
    for name in ["motor_wakeup", "motor_tick", "solver", "ipc_vision_to_core", "frame_to_schedule"] {
        let text = std::fs::read_to_string(hgrm.join(format!("{name}.hgrm"))).expect("hgrm written");
        assert!(text.contains("Total count"), "{name}.hgrm");
    }
    let _ = std::fs::remove_dir_all(&hgrm);
}

/// A client that created a service with iceoryx2's default settings before
/// the core started keeps the core from starting; the core's one line names
/// the service, what it found, what it needs, and the client's pid.
#[test]
fn a_service_created_with_other_settings_is_named_with_its_creator() {
    use iceoryx2::prelude::*;
    let prefix = common::unique_prefix("mismatch");
    let node = common::plain_node(&prefix);
    let _squatter = node
        .service_builder(&ServiceName::new(service_names::SCHEDULE).expect("name"))
        .publish_subscribe::<Schedule>()
        .open_or_create()
        .expect("a service with iceoryx2's defaults");
    let out = Command::new(common::core_exe())
        .args(["--prefix", &prefix, "--duration", "5"])
        .stderr(Stdio::piped())
        .output()
        .expect("upm-core");
    drop(_squatter);
    drop(node);
    common::remove_prefix(&prefix);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "the core started: {err}");
    let line = err.lines().find(|l| l.contains("error")).unwrap_or_default();
    eprintln!("{line}");
    for want in [
        "service upm/schedule",
        "it exists with payload upm::Schedule.v5",
        "where UPM needs 4, 16, 8, 1, true, 32",
        &format!("created by a client still running: pid {}", std::process::id()),
    ] {
        assert!(line.contains(want), "{want:?} missing from: {line}");
    }
}
