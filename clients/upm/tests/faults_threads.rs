//! No silent failure: a core thread that panics, and a driver that faults
//! (both injected through the test-only `fault-injection` feature).
//!
//! - A panicking motor, solver or receiver thread: the core holds the
//!   plate, telemetry's health names the thread and the panic, the RT
//!   threads do not allocate, and upm-core exits 1 with a one-line error.
//! - A driver fault: the core holds within a tick (lock-step tests check the
//!   tick), counts it, stays in hold until `upm resume`, or until
//!   `safety.auto_resume_ms` of healthy reads.

mod common;

use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use ipc_types::ports::Sub;
use ipc_types::rig_node::rig_node;
use ipc_types::{CoreState, HealthCause, HealthSource, Telemetry, service_names};

struct Rig {
    core: Child,
    prefix: String,
    stop_feed: Arc<AtomicBool>,
    feeder: Option<std::thread::JoinHandle<()>>,
    /// Taken in `drop` before the prefix's files are removed: ports alive
    /// then would leave them behind.
    ports: Option<(Sub<Telemetry>, Node<ipc::Service>)>,
}

impl Rig {
    /// upm-core with `UPM_INJECT_FAULT=fault`, fed the §3.1 inputs.
    fn start(tag: &str, fault: &str, config: Option<&str>) -> Self {
        let prefix = common::unique_prefix(tag);
        let mut cmd = Command::new(common::core_exe());
        cmd.args(["--prefix", &prefix]).env("UPM_INJECT_FAULT", fault).stderr(Stdio::piped());
        let cfg = std::env::temp_dir().join(format!("{prefix}.toml"));
        if let Some(text) = config {
            std::fs::write(&cfg, text).expect("config");
            cmd.arg("--config").arg(&cfg);
        }
        let core = cmd.spawn().expect("upm-core");
        let node = rig_node(&prefix, None, SignalHandlingMode::Disabled).expect("node");
        let telemetry =
            ipc_types::ports::subscriber::<Telemetry>(&node, service_names::TELEMETRY).expect("subscriber");
        let stop_feed = Arc::new(AtomicBool::new(false));
        let feeder = {
            let (p, stop) = (prefix.clone(), stop_feed.clone());
            std::thread::spawn(move || common::feed(&p, Duration::from_millis(10), &stop))
        };
        Self { core, prefix, stop_feed, feeder: Some(feeder), ports: Some((telemetry, node)) }
    }

    fn until(&mut self, within: Duration, want: impl Fn(&Telemetry) -> bool) -> Option<Telemetry> {
        let start = Instant::now();
        while start.elapsed() < within {
            let Some((telemetry, _)) = &self.ports else { return None };
            while let Some(s) = telemetry.receive().expect("receive") {
                if want(s.payload()) {
                    return Some(*s.payload());
                }
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        None
    }

    fn exit(&mut self, within: Duration) -> Option<std::process::ExitStatus> {
        let start = Instant::now();
        while start.elapsed() < within {
            if let Ok(Some(s)) = self.core.try_wait() {
                return Some(s);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        None
    }

    fn stderr(&mut self) -> String {
        let mut s = String::new();
        if let Some(mut e) = self.core.stderr.take() {
            use std::io::Read;
            let _ = e.read_to_string(&mut s);
        }
        s
    }
}

impl Drop for Rig {
    fn drop(&mut self) {
        self.stop_feed.store(true, Ordering::Relaxed);
        if let Some(f) = self.feeder.take() {
            let _ = f.join();
        }
        // SAFETY: kill(2) on our own child.
        unsafe { libc::kill(self.core.id() as libc::pid_t, libc::SIGINT) };
        if self.exit(Duration::from_secs(10)).is_none() {
            let _ = self.core.kill();
            let _ = self.core.wait();
        }
        let _ = std::fs::remove_file(std::env::temp_dir().join(format!("{}.toml", self.prefix)));
        drop(self.ports.take());
        common::remove_prefix(&self.prefix);
    }
}

fn thread_panic_is_held_reported_and_fatal(source: HealthSource) {
    let mut rig = Rig::start(source.as_str(), &format!("{source}:1500"), None);
    let running = rig.until(Duration::from_secs(20), |t| t.core_state() == Some(CoreState::Running));
    assert!(running.is_some(), "the core never ran");
    let t = rig
        .until(Duration::from_secs(5), |t| t.health_source != 0)
        .unwrap_or_else(|| panic!("{source}: no health report within 5 s"));
    assert_eq!(t.health(), Some((source, HealthCause::Panicked)));
    assert!(t.health_detail_str().contains("injected fault"), "detail: {}", t.health_detail_str());
    let held =
        rig.until(Duration::from_secs(1), |t| t.core_state() == Some(CoreState::Fault)).expect("state fault");
    if source != HealthSource::MotorThread {
        // The motor lives on and holds the plate at home.
        let home = rig.until(Duration::from_secs(1), |t| [t.plate_x, t.plate_y, t.plate_theta] == [0.0; 3]);
        assert!(home.is_some(), "{source}: the plate was not held at home");
    }
    assert_eq!(held.counters.rt_thread_allocations, 0, "{source}: the panic path allocated on an RT thread");
    let status = rig.exit(Duration::from_secs(10)).expect("upm-core did not exit after the fault");
    assert_eq!(status.code(), Some(1), "{source}: exit status {status}");
    let err = rig.stderr();
    let line = err.lines().find(|l| l.starts_with("upm-core: error:")).unwrap_or_default();
    assert!(
        line.contains(source.as_str()) && line.contains("panicked") && line.contains("injected fault"),
        "{source}: error line {line:?} in\n{err}"
    );
    assert!(!err.contains("stopped cleanly"), "{err}");
}

#[test]
fn a_panicking_motor_thread_is_reported_and_fatal() {
    thread_panic_is_held_reported_and_fatal(HealthSource::MotorThread);
}

#[test]
fn a_panicking_solver_thread_is_held_reported_and_fatal() {
    thread_panic_is_held_reported_and_fatal(HealthSource::SolverThread);
}

#[test]
fn a_panicking_receiver_thread_is_held_reported_and_fatal() {
    thread_panic_is_held_reported_and_fatal(HealthSource::ReceiverThread);
}

#[test]
fn a_driver_fault_holds_until_upm_resume() {
    let mut rig = Rig::start("drvfault", "driver:1500:300", None);
    assert!(rig.until(Duration::from_secs(20), |t| t.core_state() == Some(CoreState::Running)).is_some());
    let t = rig
        .until(Duration::from_secs(5), |t| t.core_state() == Some(CoreState::Hold) && t.health_source != 0)
        .expect("no fault hold");
    assert_eq!(t.health(), Some((HealthSource::Driver, HealthCause::DriverReadFault)));
    assert_eq!(t.counters.fault_holds, 1);
    assert!(t.counters.driver_faults >= 1);
    // The faults end after 300 ms; the hold does not end by itself.
    std::thread::sleep(Duration::from_secs(1));
    let t = rig.until(Duration::from_secs(1), |_| true).expect("telemetry");
    assert_eq!(t.core_state(), Some(CoreState::Hold), "left the fault hold without a resume");
    assert!(t.counters.driver_faults >= 2, "300 ms of faults at 10 kHz: {}", t.counters.driver_faults);
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["resume", "--prefix", &rig.prefix])
        .output()
        .expect("upm resume");
    assert!(out.status.success(), "upm resume: {}", String::from_utf8_lossy(&out.stderr));
    let t = rig
        .until(Duration::from_secs(3), |t| t.core_state() == Some(CoreState::Running))
        .expect("did not run again after upm resume");
    assert_eq!((t.counters.resumes, t.health_source), (1, 0));
}

#[test]
fn a_driver_fault_ends_after_auto_resume_ms_of_healthy_reads() {
    let config = "[safety]\nauto_resume_ms = 200.0\n";
    let mut rig = Rig::start("drvauto", "driver:1500:300", Some(config));
    assert!(rig.until(Duration::from_secs(20), |t| t.core_state() == Some(CoreState::Running)).is_some());
    let held = rig
        .until(Duration::from_secs(5), |t| t.core_state() == Some(CoreState::Hold) && t.health_source != 0)
        .expect("no fault hold");
    let start = Instant::now();
    let t = rig
        .until(Duration::from_secs(3), |t| t.core_state() == Some(CoreState::Running))
        .expect("did not resume by itself");
    // 300 ms of faults + 200 ms of healthy reads, less what had passed.
    assert!(start.elapsed() >= Duration::from_millis(150), "resumed after {:?}", start.elapsed());
    assert_eq!((held.counters.fault_holds, t.counters.resumes, t.health_source), (1, 1, 0));
}

#[test]
fn upm_status_finds_a_running_rig_without_being_told_its_prefix() {
    let mut rig = Rig::start("discover", "none", None);
    assert!(rig.until(Duration::from_secs(20), |t| t.core_state().is_some()).is_some());
    let out =
        Command::new(env!("CARGO_BIN_EXE_upm")).args(["status", "--json"]).output().expect("upm status");
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    // Other tests may run rigs at the same time: then it lists them all.
    if out.status.success() {
        assert!(stdout.contains(&format!("\"prefix\": \"{}\"", rig.prefix)), "{stdout}");
    } else {
        assert!(stderr.contains("rigs are running") && stderr.contains(&rig.prefix), "{stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    }
}
