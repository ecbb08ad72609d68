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
use upm_commands::status::read_telemetry;

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
        "it exists with payload upm::Schedule.v6",
        "where UPM needs 4, 16, 8, 1, true, 32",
        &format!("created by a client still running: pid {}", std::process::id()),
    ] {
        assert!(line.contains(want), "{want:?} missing from: {line}");
    }
}

/// The rig describes itself over the wire: a client on `ipc-types` alone
/// (no config file) reads `RigInfo` from a running core, twice (history 1
/// hands it to a late subscriber too), and it is the rig the core was
/// configured as.
#[test]
fn a_client_reads_the_rig_description_from_a_running_core() {
    use ipc_types::{PROTOCOL_VERSION, RigInfo, ValidationLimits};
    let prefix = common::unique_prefix("riginfo");
    let dir = std::env::temp_dir().join(format!("{prefix}cfg"));
    std::fs::create_dir_all(&dir).expect("dir");
    let config = dir.join("rig.toml");
    let centers = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5], [0.0, 0.8]];
    std::fs::write(
        &config,
        format!(
            "[plate]\nhalf_extent = [1.0, 0.5]\nmu_m_g = 0.12\ncenters = {centers:?}\n\n\
             [safety]\nparts_max_age_ms = 150.0\nrequest_max_age_ms = 250.0\n\n[vision]\nframe_hz = 50.0\n"
        ),
    )
    .expect("config");
    let core = Command::new(common::core_exe())
        .args(["--prefix", &prefix, "--duration", "60", "--config"])
        .arg(&config)
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn upm-core");
    let core = Core(core);
    let pid = core.0.id();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        assert!(wait_state(&prefix, CoreState::Idle, Duration::from_secs(20)), "core came up idle");
        let node = common::plain_node(&prefix);
        let read = || {
            let sub =
                ipc_types::ports::subscriber::<RigInfo>(&node, service_names::RIG_INFO).expect("subscriber");
            let start = Instant::now();
            while start.elapsed() < Duration::from_secs(5) {
                if let Some(s) = sub.receive().expect("receive") {
                    return Some((*s.payload(), start.elapsed()));
                }
                std::thread::sleep(Duration::from_millis(1));
            }
            None
        };
        let (info, after) = read().expect("the core's RigInfo arrives");
        let (again, _) = read().expect("a later subscriber gets it too");
        assert_eq!(again, info);
        eprintln!("RigInfo after {after:?}: {info:?}");
        assert_eq!(info.validate(&ValidationLimits::new([1.0, 0.5], ipc_types::monotonic_now_ns())), Ok(()));
        assert_eq!(info.protocol_version, PROTOCOL_VERSION);
        assert_eq!(info.core_pid, pid);
        assert_eq!(info.prefix_str(), prefix);
        assert_eq!((info.mu_m_g, info.plate_half_extent), (0.12, [1.0, 0.5]));
        assert_eq!((info.parts_max_age_ms, info.request_max_age_ms), (150.0, 250.0));
        assert_eq!((info.vision_frame_hz, info.max_future_skew_ms), (50.0, 1.0));
        assert_eq!((info.cycle_slots, info.slot_ticks, info.tick_hz), (0, 40, 10_000.0));
        assert_eq!(info.cycle_period_ns, 5 * 40 * 100_000, "5 slots of 40 ticks at 10 kHz");
        let got: Vec<[f64; 2]> = info.centers().iter().map(|c| [c.x, c.y]).collect();
        assert_eq!(got, centers);
        assert!(info.centers().iter().all(|c| c.k_bound > 0.0 && c.k_bound <= info.k_max), "{info:?}");
        // The most one part can get: at most μmg·k_max, and more than a
        // single center's share.
        assert!(info.max_part_force_n <= 0.12 * info.k_max && info.max_part_force_n > 0.12 * 0.5 / 5.0);
    }));
    drop(core);
    common::remove_prefix(&prefix);
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(p) = result {
        std::panic::resume_unwind(p);
    }
}
