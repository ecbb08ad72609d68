//! Message builders and iceoryx2 isolation shared by the core tests.
#![allow(dead_code, unused_imports)]

pub use upm_bench::feeder::{PAPER_PARTS, part_states, request};

/// The RT core's binary, as `upm run` finds it: `UPM_CORE_EXE`, else
/// `upm-core` next to the `upm` under test. `cargo test --workspace` builds
/// it (with fault injection); `cargo test -p upm-cli` does not, since it is
/// another package's.
pub fn core_exe() -> std::path::PathBuf {
    if let Some(p) = std::env::var_os("UPM_CORE_EXE") {
        return p.into();
    }
    let exe = std::path::Path::new(env!("CARGO_BIN_EXE_upm")).with_file_name("upm-core");
    assert!(
        exe.is_file(),
        "{} is missing: build it with `cargo test --release -p upm-core --no-run` (or test the workspace)",
        exe.display()
    );
    exe
}

/// A service prefix no other test or rig uses.
pub fn unique_prefix(tag: &str) -> String {
    ipc_types::rig_node::unique_prefix(&format!("upmt_{tag}"))
}

/// A plain iceoryx2 node on `prefix`: no signal handling, and unlike
/// `rig_node` it leaves the prefix's file permissions as they are.
pub fn plain_node(prefix: &str) -> iceoryx2::prelude::Node<iceoryx2::prelude::ipc::Service> {
    use iceoryx2::prelude::*;
    let config = ipc_types::ports::config_with_prefix(prefix).expect("prefix");
    NodeBuilder::new()
        .config(&config)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .expect("node")
}

/// Remove the per-prefix segment iceoryx2 leaves in /dev/shm.
pub fn remove_prefix(prefix: &str) {
    ipc_types::rig_node::remove_prefix_segment(prefix);
}

/// Publish the §3.1 inputs on `prefix` every `period` until `stop`.
pub fn feed(prefix: &str, period: std::time::Duration, stop: &std::sync::atomic::AtomicBool) {
    upm_bench::feeder::feed(prefix, period, stop).expect("feeder");
}

/// A Python that can `import iceoryx2` 0.10: `UPM_PYTHON`, else a venv
/// under target/tmp with `pip install iceoryx2==0.10.0` (made once).
pub fn python_with_iceoryx2() -> std::path::PathBuf {
    match std::env::var_os("UPM_PYTHON") {
        Some(p) => p.into(),
        None => venv("upm-python", "iceoryx2", "iceoryx2==0.10.0"),
    }
}

/// A venv under target/tmp named `name` whose Python can `import module`
/// (pip-installing `package` into it the first time).
pub fn venv(name: &str, module: &str, package: &str) -> std::path::PathBuf {
    use std::path::Path;
    use std::process::Command;
    let venv = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let py = venv.join("bin/python");
    let imports = |py: &Path| {
        Command::new(py).args(["-c", &format!("import {module}")]).output().is_ok_and(|o| o.status.success())
    };
    if !imports(&py) {
        // --clear: a venv left half-made by an interrupted run starts over.
        run_ok(Command::new("python3").args(["-m", "venv", "--clear"]).arg(&venv));
        run_ok(Command::new(venv.join("bin/pip")).args([
            "install",
            "--quiet",
            "--disable-pip-version-check",
            package,
        ]));
    }
    assert!(imports(&py), "{} cannot import {module}", py.display());
    py
}

/// Run `cmd`; panic with its output unless it succeeds.
pub fn run_ok(cmd: &mut std::process::Command) {
    let o = cmd.output().unwrap_or_else(|e| panic!("{cmd:?}: {e}"));
    assert!(
        o.status.success(),
        "{cmd:?}: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// `upm` as under test, run from the repository's root.
pub fn upm() -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_upm"));
    c.current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    c
}

/// A free localhost port (the OS's choice, released at once).
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0").and_then(|l| l.local_addr()).map(|a| a.port()).expect("a port")
}

/// Add user `name` with `password` to the users file `users`
/// (`upm users add … --password-stdin`).
pub fn add_user(users: &std::path::Path, name: &str, password: &str) {
    use std::io::Write as _;
    let mut c = upm()
        .args(["users", "add"])
        .arg(users)
        .args([name, "--password-stdin"])
        .stdin(std::process::Stdio::piped())
        .spawn()
        .expect("upm users add");
    c.stdin.take().expect("stdin").write_all(format!("{password}\n").as_bytes()).expect("password");
    assert!(c.wait().expect("wait").success(), "upm users add failed");
}

/// The JSON object on the last line of a successful command's stdout;
/// panics with its output otherwise.
pub fn json_of(o: &std::process::Output, what: &str) -> serde_json::Value {
    assert!(
        o.status.success(),
        "{what}: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let text = String::from_utf8_lossy(&o.stdout);
    serde_json::from_str(text.lines().last().unwrap_or("")).unwrap_or_else(|e| panic!("{what}: {e}: {text}"))
}

/// An empty directory of this test process's own under the system's
/// temporary directory (`upm_TAG_PID`), emptied if it was left behind.
pub fn fresh_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("upm_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a fresh temporary directory");
    dir
}
