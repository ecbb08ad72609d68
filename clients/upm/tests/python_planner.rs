//! A planner written in Python against `clients/python` (iceoryx2's own
//! Python package and the ctypes mirrors of the messages), run by the
//! launcher as `upm run --planner-cmd`: its requests are answered and none
//! is rejected. The test installs what it needs (a venv with the package
//! and iceoryx2 from PyPI) under target/tmp, or uses `UPM_PYTHON`.

use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// A Python that can `import upm_ipc` (installing it once if needed).
fn python() -> PathBuf {
    if let Some(p) = std::env::var_os("UPM_PYTHON") {
        return PathBuf::from(p);
    }
    let venv = Path::new(env!("CARGO_TARGET_TMPDIR")).join("upm-python");
    let py = venv.join("bin/python");
    let imports = |py: &Path| {
        Command::new(py).args(["-c", "import upm_ipc"]).output().is_ok_and(|o| o.status.success())
    };
    if !imports(&py) {
        let run = |cmd: &mut Command| {
            let o = cmd.output().expect("runs");
            assert!(
                o.status.success(),
                "{cmd:?}: {}{}",
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            );
        };
        run(Command::new("python3").args(["-m", "venv"]).arg(&venv));
        run(Command::new(venv.join("bin/pip"))
            .args(["install", "--quiet", "--disable-pip-version-check"])
            .arg(Path::new(ROOT).join("clients/python")));
    }
    assert!(imports(&py), "{} cannot import upm_ipc", py.display());
    py
}

#[test]
fn a_python_planner_drives_the_rig_through_upm_run() {
    let py = python();
    let out = std::env::temp_dir().join(format!("upm_run_python_{}", std::process::id()));
    let planner = format!("exec '{}' clients/python/examples/gather.py", py.display());
    let o = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["run", "local", "--duration", "6", "--quiet", "--planner-cmd", &planner, "--out"])
        .arg(&out)
        .current_dir(ROOT)
        .output()
        .expect("upm run");
    let log = std::fs::read_to_string(out.join("logs/planner.log")).unwrap_or_default();
    assert!(o.status.success(), "{}\nplanner.log:\n{log}", String::from_utf8_lossy(&o.stderr));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics"))
            .expect("json");
    let _ = std::fs::remove_dir_all(&out);
    assert!(m["schedules_seen"].as_u64().unwrap_or(0) > 0, "no request answered: {m}\n{log}");
    assert_eq!(m["core"]["rejected_requests"], 0, "{m}\n{log}");
    assert_eq!(m["restarts"]["planner"], 0, "the Python planner died: {m}\n{log}");
    // It stopped cleanly on the launcher's SIGINT and says how many it sent.
    let sent: u64 = log
        .lines()
        .find_map(|l| l.strip_prefix("gather.py: ")?.strip_suffix(" requests")?.parse().ok())
        .unwrap_or(0);
    assert!(sent > 0, "planner.log: {log}");
}
