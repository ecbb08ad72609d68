//! `upm run` and the clients it supervises, as a user's planner command
//! meets them: nothing outlives the run (a grandchild that ignores SIGINT
//! and SIGTERM included), however the run ends; every client event is one
//! line naming the command, the status and the log; a crash loop, and a
//! planner that never gets a request accepted, end the run non-zero; a hung
//! planner is killed with its group and restarted.
//!
//! Each test has its own prefix and output directory and removes them.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
const UPM: &str = env!("CARGO_BIN_EXE_upm");

fn temp(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("upm_sup_{tag}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    dir
}

/// One rig at a time: each pins its motor thread to the same CPU.
static ONE_RIG: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// `upm run local` with `planner` as `--planner-cmd`, started (not waited).
fn start_run(prefix: &str, seconds: &str, planner: &str, out: &Path) -> Child {
    Command::new(UPM)
        .args(["run", "local", "--prefix", prefix, "--duration", seconds, "--quiet", "--no-record"])
        .args(["--planner-cmd", planner, "--out"])
        .arg(out)
        .current_dir(ROOT)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("upm run")
}

fn finish(child: Child, within: Duration) -> Output {
    let pid = child.id();
    let waiter = std::thread::spawn(move || child.wait_with_output().expect("wait"));
    let start = Instant::now();
    while !waiter.is_finished() {
        if start.elapsed() > within {
            // SAFETY: kill(2) on our own child, so the test ends.
            unsafe { libc::kill(pid as libc::pid_t, libc::SIGKILL) };
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    waiter.join().expect("waiter")
}

fn wait_for_pid(file: &Path, within: Duration) -> u32 {
    let start = Instant::now();
    loop {
        if let Some(p) = std::fs::read_to_string(file).ok().and_then(|t| t.trim().parse().ok()) {
            return p;
        }
        assert!(start.elapsed() < within, "{} never appeared", file.display());
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The built-in planner behind a shell that first starts a grandchild
/// which ignores SIGINT and SIGTERM and writes its pid to `pidfile`.
fn planner_with_stubborn_grandchild(pidfile: &Path) -> String {
    format!(
        "(trap '' INT TERM; exec sleep 600) & echo $! > '{}'; exec '{UPM}' planner --config \"$UPM_CONFIG\"",
        pidfile.display()
    )
}

fn pid_of_core(out: &Path) -> Option<i32> {
    let pattern = format!("upm-core --config {}", out.join("config.toml").display());
    let ps = Command::new("pgrep").args(["-f", &pattern]).output().ok()?;
    String::from_utf8_lossy(&ps.stdout).split_whitespace().next()?.parse().ok()
}

/// The run's metrics.json.
fn metrics(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics")).expect("json")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[derive(Debug, Clone, Copy)]
enum End {
    Normal,
    CtrlC,
    CoreDied,
}

fn nothing_outlives_the_run(end: End) {
    let _turn = ONE_RIG.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let prefix = common::unique_prefix(&format!("orphan_{end:?}"));
    let dir = temp(&format!("orphan_{end:?}"));
    let out = dir.join("run");
    let pidfile = dir.join("grandchild.pid");
    let seconds = if matches!(end, End::Normal) { "4" } else { "60" };
    let run = start_run(&prefix, seconds, &planner_with_stubborn_grandchild(&pidfile), &out);
    let grandchild = wait_for_pid(&pidfile, Duration::from_secs(30));
    assert!(upm_commands::launcher::process_group::running(grandchild));
    match end {
        End::Normal => {}
        End::CtrlC => {
            std::thread::sleep(Duration::from_secs(2));
            // SAFETY: kill(2) on our own child.
            unsafe { libc::kill(run.id() as libc::pid_t, libc::SIGINT) };
        }
        End::CoreDied => {
            std::thread::sleep(Duration::from_secs(2));
            let core = pid_of_core(&out).expect("core pid");
            // SAFETY: kill(2) on the core this test's run started.
            unsafe { libc::kill(core, libc::SIGKILL) };
        }
    }
    let o = finish(run, Duration::from_secs(60));
    let stderr = text(&o.stderr);
    common::remove_prefix(&prefix);
    assert!(
        !upm_commands::launcher::process_group::running(grandchild),
        "{end:?}: the planner's grandchild {grandchild} outlived upm run\n{stderr}"
    );
    match end {
        End::CoreDied => {
            assert!(!o.status.success(), "a dead core is a failed run");
            assert!(stderr.contains("core (upm-core) was killed by signal 9 (SIGKILL) after"), "{stderr}");
            assert!(stderr.contains("logs/core.log"), "{stderr}");
        }
        _ => assert!(o.status.success(), "{end:?}: {:?}\n{stderr}", o.status),
    }
    if matches!(end, End::Normal) {
        let summary = text(&o.stdout);
        assert!(summary.starts_with("local seed 1: "), "a summary for a person, not JSON: {summary}");
        assert!(summary.lines().count() <= 5, "{summary}");
        let m = metrics(&out);
        let planner = &m["clients"]["planner"];
        assert!(planner["command"].as_str().is_some_and(|c| c.starts_with("planner command \"(trap")), "{m}");
        assert_eq!(planner["restarts"], 0, "{m}");
        assert!(planner["last_exit"].as_str().is_some_and(|e| e.ends_with("when stopped")), "{m}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_grandchild_that_ignores_sigterm_is_gone_after_a_normal_end() {
    nothing_outlives_the_run(End::Normal);
}

#[test]
fn a_grandchild_that_ignores_sigterm_is_gone_after_ctrl_c() {
    nothing_outlives_the_run(End::CtrlC);
}

#[test]
fn a_grandchild_that_ignores_sigterm_is_gone_after_the_core_died() {
    nothing_outlives_the_run(End::CoreDied);
}

/// A planner that fails at start: each exit is one line with the command,
/// the status, the time, the log's last line and the log; after a few in
/// a row the run stops non-zero with that line.
#[test]
fn a_crash_loop_ends_the_run_non_zero_naming_the_command_status_and_log() {
    let _turn = ONE_RIG.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let prefix = common::unique_prefix("crashloop");
    let dir = temp("crashloop");
    let out = dir.join("run");
    let cmd = "echo 'Traceback (most recent call last):' >&2; \
               echo \"ModuleNotFoundError: No module named 'upm_ipc'\" >&2; exit 1";
    let o = finish(start_run(&prefix, "60", cmd, &out), Duration::from_secs(60));
    let stderr = text(&o.stderr);
    common::remove_prefix(&prefix);
    assert!(!o.status.success(), "{stderr}");
    let log = out.join("logs/planner.log").display().to_string();
    let event = format!("upm run: planner command {cmd:?} exited with status 1 after ");
    let cause = format!(" s (ModuleNotFoundError: No module named 'upm_ipc'; {log}); restart 1 in 0.1 s");
    let first = stderr.lines().find(|l| l.starts_with(&event)).unwrap_or_else(|| panic!("{stderr}"));
    assert!(first.ends_with(&cause), "{first}");
    assert!(!stderr.contains("died"), "{stderr}");
    let last = stderr.lines().last().unwrap_or_default();
    assert!(
        last.starts_with(&format!("upm: error: planner command {cmd:?} exited with status 1 after ")),
        "{last}"
    );
    assert!(
        last.contains(&format!(
            "; {log}); 3 failures in a row, each within 5 s of its start, so the run stops"
        )),
        "{last}"
    );
    assert!(!last.contains("restart 3"), "{last}");
    let m = metrics(&out);
    assert_eq!(m["clients"]["planner"]["restarts"], 2, "{m}");
    assert!(
        m["clients"]["planner"]["last_exit"].as_str().is_some_and(|e| e.starts_with("exited with status 1"))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A planner that runs but never sends: the run ends non-zero and says so.
#[test]
fn a_planner_that_never_had_a_request_accepted_fails_the_run() {
    let _turn = ONE_RIG.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let prefix = common::unique_prefix("silent");
    let dir = temp("silent");
    let out = dir.join("run");
    let o = finish(start_run(&prefix, "3", "exec sleep 600", &out), Duration::from_secs(60));
    let stderr = text(&o.stderr);
    common::remove_prefix(&prefix);
    assert!(!o.status.success(), "{stderr}");
    assert!(
        stderr.contains("the planner command \"exec sleep 600\" never had a request accepted in"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A planner that works, then stops (SIGSTOP: alive, silent) is found hung,
/// killed with its group, restarted and named; the run goes on.
#[test]
fn a_hung_planner_is_killed_with_its_group_restarted_and_named() {
    let _turn = ONE_RIG.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let prefix = common::unique_prefix("hung");
    let dir = temp("hung");
    let out = dir.join("run");
    let cmd = format!("exec timeout -s STOP 3 '{UPM}' planner --config \"$UPM_CONFIG\"");
    let o = finish(start_run(&prefix, "14", &cmd, &out), Duration::from_secs(90));
    let stderr = text(&o.stderr);
    common::remove_prefix(&prefix);
    assert!(o.status.success(), "{stderr}");
    let hung = format!("upm run: planner command {cmd:?} is hung (alive, but no request accepted for ");
    assert!(stderr.contains(&hung), "{stderr}");
    assert!(stderr.contains("and was killed with its process group after"), "{stderr}");
    let m = metrics(&out);
    assert!(m["clients"]["planner"]["hung_kills"].as_u64() >= Some(1), "{m}");
    assert!(m["clients"]["planner"]["restarts"].as_u64() >= Some(1), "{m}");
    let _ = std::fs::remove_dir_all(&dir);
}
