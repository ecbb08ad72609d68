//! Faults: kill -9 of a client or of the core in the middle of a run.
//!
//! - A killed vision or planner puts the core in hold well under a second
//!   later, with the plate at home (a cycle is never left half played); the
//!   launcher restarts the client and the core runs again.
//! - A killed core makes `upm run` stop its clients and say so, keeping what
//!   it recorded; a new `upm run` on the same prefix right after works.
//! - Clients started by hand notice a dead core, wait, and serve a new one.
//! - The prefix's shared memory is owner-only.
//!
//! Each test has its own prefix and removes what it created. The kill→hold
//! times are printed (run with --nocapture), not asserted beyond the 1 s
//! safety bound.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use ipc_types::ports::Sub;
use ipc_types::rig_node::{files_open_to_others, rig_node};
use ipc_types::{CoreState, Telemetry, service_names};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// A child process killed (and reaped) when the test ends, however it ends.
struct Proc(Child);

impl Drop for Proc {
    fn drop(&mut self) {
        // SIGINT first: `upm run` then stops its rig; SIGKILL if it hangs.
        if self.interrupt_and_wait(Duration::from_secs(10)).is_none() {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

impl Proc {
    fn interrupt_and_wait(&mut self, within: Duration) -> Option<std::process::ExitStatus> {
        if let Ok(Some(s)) = self.0.try_wait() {
            return Some(s);
        }
        // SAFETY: kill(2) on our own child.
        unsafe { libc::kill(self.0.id() as libc::pid_t, libc::SIGINT) };
        let start = Instant::now();
        while start.elapsed() < within {
            if let Ok(Some(s)) = self.0.try_wait() {
                return Some(s);
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        None
    }

    /// Everything it wrote to stderr; kills it first if it still runs (the
    /// read only ends at EOF).
    fn stderr(&mut self) -> String {
        if !matches!(self.0.try_wait(), Ok(Some(_))) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
        let mut s = String::new();
        if let Some(mut e) = self.0.stderr.take() {
            use std::io::Read;
            let _ = e.read_to_string(&mut s);
        }
        s
    }
}

/// The newest telemetry of the core on a prefix, sample by sample.
struct TelemetryWatch {
    sub: Sub<Telemetry>,
    _node: Node<ipc::Service>,
}

impl TelemetryWatch {
    fn new(prefix: &str) -> Self {
        let node = rig_node(prefix, None, SignalHandlingMode::Disabled).expect("node");
        let sub =
            ipc_types::ports::subscriber::<Telemetry>(&node, service_names::TELEMETRY).expect("subscriber");
        Self { sub, _node: node }
    }

    /// The first sample (and when it arrived) for which `want` holds. Looks
    /// at least once, so `within = 0` drains what is buffered.
    fn until(&self, within: Duration, want: impl Fn(&Telemetry) -> bool) -> Option<(Telemetry, Instant)> {
        let start = Instant::now();
        loop {
            while let Some(s) = self.sub.receive().expect("receive") {
                if want(s.payload()) {
                    return Some((*s.payload(), Instant::now()));
                }
            }
            if start.elapsed() >= within {
                return None;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    fn state(&self, want: CoreState, within: Duration) -> Option<(Telemetry, Instant)> {
        self.until(within, |t| t.core_state() == Some(want))
    }
}

fn upm(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_upm"));
    c.args(args).current_dir(ROOT).stdout(Stdio::null()).stderr(Stdio::piped());
    c
}

fn upm_run(scenario: &str, prefix: &str, seconds: &str, out: &Path) -> Proc {
    let mut c = upm(&["run", scenario, "--prefix", prefix, "--duration", seconds, "--quiet", "--out"]);
    Proc(c.arg(out).spawn().expect("upm run"))
}

/// Pid of the `upm-ROLE --config CFG` (or `upm ROLE …`) process, if one runs.
fn pid_of(role: &str, cfg: &Path) -> Option<i32> {
    let pattern = format!("upm[- ]{role} --config {}", cfg.display());
    let ps = Command::new("pgrep").args(["-f", &pattern]).output().ok()?;
    String::from_utf8_lossy(&ps.stdout).split_whitespace().next()?.parse().ok()
}

fn wait_pid(role: &str, cfg: &Path, not: Option<i32>, within: Duration) -> Option<i32> {
    let start = Instant::now();
    while start.elapsed() < within {
        if let Some(p) = pid_of(role, cfg)
            && Some(p) != not
        {
            return Some(p);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    None
}

fn kill9(pid: i32) {
    // SAFETY: kill(2) on a process this test started (through `upm run`).
    unsafe { libc::kill(pid, libc::SIGKILL) };
}

fn temp(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("upm_{tag}_{}", std::process::id()))
}

fn metrics(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics.json"))
        .expect("json")
}

/// The spin scenario with a fast camera and a staleness limit (60 ms) below
/// the launcher's first restart backoff (100 ms), so a killed client always
/// causes a hold; telemetry every 5 ms to see it promptly.
fn fast_spin_scenario(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(Path::new(ROOT).join("scenarios/spin.toml")).expect("spin.toml");
    let text =
        text.replace("frame_hz = 30.0", "frame_hz = 100.0").replace("latency_ms = 10.0", "latency_ms = 5.0");
    let text = format!(
        "{text}\n[rig.safety]\nparts_max_age_ms = 60.0\nrequest_max_age_ms = 60.0\n\n[rig.telemetry]\nperiod_ms = 5.0\n"
    );
    std::fs::create_dir_all(dir).expect("dir");
    let path = dir.join("spin_fast.toml");
    std::fs::write(&path, text).expect("write scenario");
    path
}

#[test]
fn a_killed_client_holds_the_core_at_home_and_it_runs_again_after_the_restart() {
    let prefix = common::unique_prefix("kc");
    let dir = temp("kill_client");
    let out = dir.join("run");
    let scenario = fast_spin_scenario(&dir);
    let mut run = upm_run(&scenario.display().to_string(), &prefix, "120", &out);
    let cfg = out.join("config.toml");
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let watch = TelemetryWatch::new(&prefix);
        assert!(watch.state(CoreState::Running, Duration::from_secs(40)).is_some(), "core never ran");
        for role in ["vision", "planner"] {
            let pid = wait_pid(role, &cfg, None, Duration::from_secs(10)).expect("client pid");
            // Let it run a little, then drain old samples and kill.
            std::thread::sleep(Duration::from_millis(500));
            let _ = watch.until(Duration::ZERO, |_| false);
            kill9(pid);
            let killed = Instant::now();
            let (t, at) = watch.state(CoreState::Hold, Duration::from_secs(10)).expect("core held");
            let hold_ms = at.duration_since(killed).as_secs_f64() * 1e3;
            eprintln!(
                "kill -9 {role}: hold after {hold_ms:.0} ms (parts age {:.0} ms, request age {:.0} ms)",
                t.parts_age_ms, t.request_age_ms
            );
            assert!(hold_ms < 1000.0, "hold came {hold_ms:.0} ms after the kill");
            assert!(t.parts_age_ms >= 60.0 || t.request_age_ms >= 60.0, "hold without stale input");
            assert_eq!(
                [t.plate_x, t.plate_y, t.plate_theta],
                [0.0; 3],
                "held plate not at home: a cycle was cut"
            );
            // While held, the plate stays home in every sample.
            let moved = watch.until(Duration::from_millis(50), |t| {
                t.core_state() == Some(CoreState::Hold)
                    && (t.plate_x, t.plate_y, t.plate_theta) != (0.0, 0.0, 0.0)
            });
            assert!(moved.is_none(), "plate moved while held");
            let new_pid = wait_pid(role, &cfg, Some(pid), Duration::from_secs(10)).expect("client restarted");
            assert_ne!(new_pid, pid);
            let (_, back) = watch.state(CoreState::Running, Duration::from_secs(20)).expect("running again");
            eprintln!(
                "kill -9 {role}: running again {:.0} ms after the kill",
                back.duration_since(killed).as_secs_f64() * 1e3
            );
        }
    }));
    let status = run.interrupt_and_wait(Duration::from_secs(30));
    let stderr = run.stderr();
    common::remove_prefix(&prefix);
    if let Err(p) = result {
        std::panic::resume_unwind(p);
    }
    assert!(status.is_some_and(|s| s.success()), "upm run: {status:?}: {stderr}");
    let m = metrics(&out);
    assert!(m["restarts"]["vision"].as_u64() >= Some(1), "{m}");
    assert!(m["restarts"]["planner"].as_u64() >= Some(1), "{m}");
    assert!(m["core"]["hold_events"].as_u64() >= Some(2), "{m}");
    assert_eq!(m["core"]["rt_thread_allocations"], 0);
    assert_eq!(m["core"]["exit_ok"], true);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn after_a_killed_core_the_next_run_on_the_same_prefix_works() {
    let prefix = common::unique_prefix("kk");
    let dir = temp("kill_core");
    let (first, second) = (dir.join("first"), dir.join("second"));
    let mut run = upm_run("spin", &prefix, "120", &first);
    let cfg = first.join("config.toml");
    let watch = TelemetryWatch::new(&prefix);
    assert!(watch.state(CoreState::Running, Duration::from_secs(40)).is_some(), "core never ran");
    let core = pid_of("core", &cfg).expect("core pid");
    kill9(core);
    let start = Instant::now();
    let status = loop {
        if let Some(s) = run.0.try_wait().expect("wait") {
            break s;
        }
        assert!(start.elapsed() < Duration::from_secs(30), "upm run did not notice the dead core");
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = run.stderr();
    assert!(!status.success());
    assert!(stderr.contains("core (upm-core) was killed by signal 9 (SIGKILL) after"), "{stderr}");
    // What was recorded up to the kill is kept.
    let m = metrics(&first);
    assert!(m["core"]["died"].as_str().is_some_and(|s| s.contains("signal 9 (SIGKILL)")), "{m}");
    assert!(first.join("trails.svg").is_file());
    for role in ["vision", "planner"] {
        assert!(pid_of(role, &cfg).is_none(), "{role} left running");
    }
    drop(watch);

    // Right away: the same prefix, the dead core's resources still there.
    let mut next = upm_run("spin", &prefix, "3", &second);
    let status = next.0.wait().expect("wait");
    let stderr = next.stderr();
    common::remove_prefix(&prefix);
    assert!(status.success(), "second run: {stderr}");
    let m = metrics(&second);
    assert_eq!(m["core"]["exit_ok"], true, "{m}");
    assert!(m["core"]["cycles"].as_u64() > Some(0), "{m}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn hand_started_clients_wait_for_a_new_core_and_serve_it() {
    let prefix = common::unique_prefix("kw");
    let dir = temp("kill_wait");
    std::fs::create_dir_all(&dir).expect("dir");
    let scenario = upm_commands::scenario::Scenario::load(&Path::new(ROOT).join("scenarios/spin.toml"))
        .expect("spin scenario");
    let config = scenario.config(1, &prefix).expect("config");
    let cfg = dir.join("config.toml");
    std::fs::write(&cfg, toml::to_string(&config).expect("toml")).expect("write config");
    let cfg_s = cfg.display().to_string();
    let core = || {
        let mut c = Command::new(common::core_exe());
        c.args(["--config", &cfg_s, "--truth-hz", "1000"]).current_dir(ROOT);
        Proc(c.stdout(Stdio::null()).stderr(Stdio::piped()).spawn().expect("core"))
    };
    let mut first_core = core();
    let watch = TelemetryWatch::new(&prefix);
    assert!(watch.state(CoreState::Idle, Duration::from_secs(30)).is_some(), "core came up");
    let mut vision = Proc(upm(&["vision", "--config", &cfg_s]).spawn().expect("vision"));
    let mut planner = Proc(upm(&["planner", "--config", &cfg_s]).spawn().expect("planner"));
    assert!(watch.state(CoreState::Running, Duration::from_secs(30)).is_some(), "loop closed");

    kill9(first_core.0.id() as i32);
    let _ = first_core.0.wait();
    std::thread::sleep(Duration::from_millis(2500));
    assert!(vision.0.try_wait().expect("wait").is_none(), "vision died with the core");
    assert!(planner.0.try_wait().expect("wait").is_none(), "planner died with the core");

    let mut second_core = core();
    let resumed = watch.until(Duration::from_secs(30), |t| {
        t.core_pid == second_core.0.id() && t.core_state() == Some(CoreState::Running)
    });
    // The clients look for the core once a second; give them time to say so.
    std::thread::sleep(Duration::from_millis(1500));
    let second_ok = second_core.interrupt_and_wait(Duration::from_secs(20));
    let (v, p) = (
        vision.interrupt_and_wait(Duration::from_secs(10)),
        planner.interrupt_and_wait(Duration::from_secs(10)),
    );
    let (vision_log, planner_log) = (vision.stderr(), planner.stderr());
    drop(watch);
    common::remove_prefix(&prefix);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(resumed.is_some(), "the new core never ran with the old clients");
    assert!(second_ok.is_some_and(|s| s.success()), "second core exit {second_ok:?}");
    assert!(v.is_some_and(|s| s.success()) && p.is_some_and(|s| s.success()), "clients exit {v:?} {p:?}");
    for log in [&vision_log, &planner_log] {
        assert!(log.contains("waiting for one"), "no notice of the dead core: {log}");
        assert!(log.matches("upm-core is up").count() >= 2, "no notice of the new core: {log}");
    }
}

#[test]
fn the_prefix_shared_memory_is_owner_only() {
    // Control: a plain iceoryx2 node leaves a file others can open, so the
    // check below can fail (iceoryx2 0.10 creates global_mgmt as 0666).
    let plain = common::unique_prefix("permctl");
    let node = common::plain_node(&plain);
    let control = files_open_to_others(&plain);
    drop(node);
    common::remove_prefix(&plain);
    assert!(!control.is_empty(), "the control found nothing open: the check would pass vacuously");

    // The core's files, observed without opening a node of our own (which
    // would tighten them itself).
    let prefix = common::unique_prefix("perm");
    let mut core = Proc(
        Command::new(common::core_exe())
            .args(["--prefix", &prefix, "--duration", "60"])
            .stderr(Stdio::null())
            .spawn()
            .expect("core"),
    );
    let start = Instant::now();
    while !ipc_types::discovery::core_running(&prefix).unwrap_or(false) {
        assert!(start.elapsed() < Duration::from_secs(30), "core never came up");
        std::thread::sleep(Duration::from_millis(20));
    }
    // Wait for its telemetry (all its services exist) through a plain node:
    // it joins the core's existing segments and tightens nothing.
    let node = common::plain_node(&prefix);
    let telemetry =
        ipc_types::ports::subscriber::<Telemetry>(&node, service_names::TELEMETRY).expect("subscriber");
    let mut up = false;
    while !up && start.elapsed() < Duration::from_secs(30) {
        while let Some(t) = telemetry.receive().expect("receive") {
            up |= t.payload().core_state() == Some(CoreState::Idle);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(up, "core never published Idle telemetry");
    let shm = std::fs::read_dir(ipc_types::rig_node::SHM_DIR)
        .map(|d| d.flatten().filter(|e| e.file_name().to_string_lossy().starts_with(&prefix)).count())
        .unwrap_or(0);
    let open = files_open_to_others(&prefix);
    drop((telemetry, node));
    let _ = core.interrupt_and_wait(Duration::from_secs(20));
    common::remove_prefix(&prefix);
    assert!(shm > 0, "found none of the prefix's shared memory");
    assert!(open.is_empty(), "shared memory others can open: {open:?}");
}
