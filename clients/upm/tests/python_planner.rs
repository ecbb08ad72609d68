//! A planner written in Python against `clients/python` (iceoryx2's own
//! Python package and the ctypes mirrors of the messages), run by the
//! launcher as `upm run --planner-cmd`: its requests are answered and none
//! is rejected. The test installs what it needs (a venv with iceoryx2 from
//! PyPI) under target/tmp, or uses `UPM_PYTHON`; the package itself is taken
//! from the source tree (PYTHONPATH), so it is always the current one.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// A Python that can `import iceoryx2` (installing it once if needed; the
/// tests of this file run in parallel, so one of them installs and the
/// others wait for it).
fn python() -> PathBuf {
    static PYTHON: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    PYTHON.get_or_init(common::python_with_iceoryx2).clone()
}

/// What `upm run SCENARIO --planner-cmd CMD` left: its output, metrics.json,
/// and the planner's and the core's logs.
struct Run {
    out: std::process::Output,
    metrics: serde_json::Value,
    /// The log of the process replaced (`logs/planner.log` or `logs/vision.log`).
    client_log: String,
    core_log: String,
}

/// `upm run` with a planner of our own.
fn upm_run(scenario: &str, seconds: &str, planner: &str, tag: &str) -> Run {
    upm_run_as("planner", scenario, seconds, planner, tag)
}

/// `upm run` with `role` ("planner" or "vision") replaced by `cmd`.
fn upm_run_as(role: &str, scenario: &str, seconds: &str, cmd: &str, tag: &str) -> Run {
    upm_run_with(role, scenario, seconds, cmd, tag, Some(&Path::new(ROOT).join("clients/python")))
}

/// `upm_run_as`, with `python_path` as PYTHONPATH (none: unset).
fn upm_run_with(
    role: &str,
    scenario: &str,
    seconds: &str,
    cmd: &str,
    tag: &str,
    python_path: Option<&Path>,
) -> Run {
    let dir = std::env::temp_dir().join(format!("upm_run_{tag}_{}", std::process::id()));
    let flag = format!("--{role}-cmd");
    let mut command = Command::new(env!("CARGO_BIN_EXE_upm"));
    command.args(["run", scenario, "--duration", seconds, "--quiet", &flag, cmd, "--out"]).arg(&dir);
    match python_path {
        Some(p) => command.env("PYTHONPATH", p),
        None => command.env_remove("PYTHONPATH"),
    };
    let out = command.current_dir(ROOT).output().expect("upm run");
    let read = |p: &str| std::fs::read_to_string(dir.join(p)).unwrap_or_default();
    let metrics = serde_json::from_str(&read("metrics.json")).unwrap_or(serde_json::Value::Null);
    let client_log = read(&format!("logs/{role}.log"));
    let run = Run { out, metrics, client_log, core_log: read("logs/core.log") };
    let _ = std::fs::remove_dir_all(&dir);
    run
}

#[test]
fn a_python_planner_drives_the_rig_through_upm_run() {
    let py = python();
    let planner = format!("exec '{}' examples/own-planner/gather.py", py.display());
    let r = upm_run("local", "6", &planner, "python");
    let (m, log) = (&r.metrics, &r.client_log);
    assert!(r.out.status.success(), "{}\nplanner.log:\n{log}", String::from_utf8_lossy(&r.out.stderr));
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

/// A refused request is answered to its sender, across languages: a Python
/// client that sends a request of another protocol version reads why on
/// `upm/rejection`, and the core's log says it too.
#[test]
fn a_python_client_is_told_why_its_request_was_refused() {
    let py = python();
    let script = r#"
import sys, upm_ipc
rig = upm_ipc.connect(__import__("os").environ["UPM_PREFIX"])
while rig.newest_part_states() is None:
    if not rig.wait(0.01): sys.exit(0)
req = upm_ipc.ForceRequest()
req.push_force(1, 0.001, 0.0)
now = upm_ipc.monotonic_now_ns()
req.protocol_version, req.seq, req.stamp_ns, req.deadline_ns = 2, 42, now, now + upm_ipc.REQUEST_LIFETIME_NS
rig.send_request(req)
while rig.wait(0.01):
    for r in rig.rejections():
        if r.seq == 42: print(f"told: {r}", flush=True)
"#;
    let script_path = std::env::temp_dir().join(format!("upm_refused_{}.py", std::process::id()));
    std::fs::write(&script_path, script).expect("script");
    let planner = format!("exec '{}' '{}'", py.display(), script_path.display());
    let r = upm_run("local", "4", &planner, "refused");
    let _ = std::fs::remove_file(&script_path);
    // Its only request was refused: the run fails, and says why.
    let stderr = String::from_utf8_lossy(&r.out.stderr);
    assert!(!r.out.status.success(), "{stderr}");
    assert!(stderr.contains("never had a request accepted in"), "{stderr}");
    assert!(stderr.contains("(1 requests rejected: wrong_protocol_version 1; see "), "{stderr}");
    let why = format!(
        "force_request seq 42 rejected: wrong_protocol_version \
         (force_request.protocol_version is 2, expected {})",
        ipc_types::PROTOCOL_VERSION
    );
    assert!(r.client_log.contains(&format!("told: {why}")), "planner.log:\n{}", r.client_log);
    assert!(r.core_log.contains(&why), "core.log:\n{}", r.core_log);
}

/// Protocol v5's outlines from Python: a vision of its own (`--vision-cmd`)
/// sends a disc, a square and a clockwise triangle, which are taken and
/// solved for the Rust planner, and four malformed outlines, each refused
/// as `bad_shape` with a line naming the field.
#[test]
fn a_python_vision_sends_outlines_and_is_told_which_field_is_malformed() {
    let py = python();
    let script = r#"
import ctypes, os, sys, upm_ipc
from upm_ipc import PartState, PartStates
rig = upm_ipc.connect(os.environ["UPM_PREFIX"], name="upm-vision-py")
pub = upm_ipc.open_pub_sub(rig.node, upm_ipc.PART_STATES, PartStates).publisher_builder().create()
wake = upm_ipc.open_inbox_event(rig.node).notifier_builder().create()
SQUARE = [(0.01, 0.01), (-0.01, 0.01), (-0.01, -0.01), (0.01, -0.01)]

def states():
    m = PartStates()
    m.push(PartState.point(1, 0, 0, (-0.3, -0.2, 0.0)).with_disc(0.015))
    m.push(PartState.point(2, 0, 0, (0.2, -0.25, 0.3)).with_polygon(SQUARE))
    m.push(PartState.point(3, 0, 0, (-0.5, 0.25, -1.0)).with_polygon([(0.02, 0.0), (-0.01, -0.015), (-0.01, 0.015)]))
    return m

def bow_tie(m): m.parts[1].with_polygon([SQUARE[0], SQUARE[2], SQUARE[1], SQUARE[3]])
def nan_radius(m): m.parts[0].radius = float("nan")
def nine_vertices(m): m.parts[2].vertex_count = 9
def shape_7(m): m.parts[0].shape = 7
BAD = [bow_tie, nan_radius, nine_vertices, shape_7]

seq, bad_seqs, start = 0, {}, upm_ipc.monotonic_now_ns()
while rig.wait(0.03):
    m = states()
    due = (upm_ipc.monotonic_now_ns() - start) / 1e9 > 0.5 + 1.2 * len(bad_seqs)
    if due and len(bad_seqs) < len(BAD):
        BAD[len(bad_seqs)](m)
        bad_seqs[seq + 1] = BAD[len(bad_seqs)].__name__
    seq += 1
    m.seq, m.stamp_ns = seq, upm_ipc.monotonic_now_ns()
    sample = pub.loan_uninit()
    ctypes.memmove(sample.payload_ptr, ctypes.byref(m), ctypes.sizeof(PartStates))
    sample.assume_init().send()
    wake.notify()
    for r in rig.rejections():
        if r.kind != 0:
            continue  # not part states
        if r.seq in bad_seqs:
            print(f"told: {r}", flush=True)
        else:
            print(f"UNEXPECTED: {r}", flush=True)
print(f"vision.py: {seq} sent, {len(bad_seqs)} malformed", flush=True)
"#;
    let script_path = std::env::temp_dir().join(format!("upm_outlines_{}.py", std::process::id()));
    std::fs::write(&script_path, script).expect("script");
    let vision = format!("exec '{}' '{}'", py.display(), script_path.display());
    let Run { out, metrics: m, client_log: log, core_log } =
        upm_run_as("vision", "local", "7", &vision, "outlines");
    let _ = std::fs::remove_file(&script_path);
    assert!(out.status.success(), "{}\nvision.log:\n{log}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(m["restarts"]["vision"], 0, "the Python vision died: {m}\n{log}");
    assert!(!log.contains("UNEXPECTED"), "a good outline was refused:\n{log}");
    for why in [
        "part_states.parts[1].vertices: the polygon must be convex, simple and of non-zero area",
        "part_states.parts[0].radius: radius must be a finite number ≥ 0.0001 m",
        "part_states.parts[2].vertex_count: a polygon needs 3 to 8 vertices",
        "part_states.parts[0].shape: must be 0 (point), 1 (disc) or 2 (polygon)",
    ] {
        assert!(log.contains(&format!(" rejected: bad_shape ({why})")), "not told {why:?}:\n{log}");
    }
    assert!(core_log.contains(" rejected: bad_shape (part_states.parts["), "core.log:\n{core_log}");
    assert_eq!(m["core"]["rejected_by_reason"]["bad_shape"], 4, "{m}");
    assert_eq!(m["core"]["rejected_parts"], 4, "{m}");
    // The shaped parts were taken and solved: the Rust planner was answered.
    assert!(m["schedules_seen"].as_u64().unwrap_or(0) > 0, "no request answered: {m}\n{log}");
}

/// A stranger's planner (`tests/stranger/planner.py`): its message layouts,
/// service names and settings are read from docs/protocol.md's tables when
/// it starts, checked against the doc's offsets and sizes, and used with
/// iceoryx2's own Python package only (no `clients/python`). It learns the
/// rig from the rig-info service, wakes on vision's event, and matches its
/// answers and refusals the way the doc says. Its requests are answered,
/// none is refused, and nothing of it runs once `upm run` has ended.
#[test]
fn a_planner_built_from_the_protocol_doc_alone_is_answered_and_leaves_nothing_behind() {
    let py = python();
    let pidfile = std::env::temp_dir().join(format!("upm_stranger_{}.pid", std::process::id()));
    let _ = std::fs::remove_file(&pidfile);
    let planner = format!(
        "exec '{}' '{}/clients/upm/tests/stranger/planner.py' '{ROOT}/docs/protocol.md' '{}'",
        py.display(),
        ROOT,
        pidfile.display()
    );
    let Run { out, metrics: m, client_log: log, .. } =
        upm_run_with("planner", "local", "6", &planner, "stranger", None);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}\nplanner.log:\n{log}");
    let pid: u32 =
        std::fs::read_to_string(&pidfile).ok().and_then(|t| t.trim().parse().ok()).expect("planner pid");
    let _ = std::fs::remove_file(&pidfile);
    assert!(
        !upm_commands::launcher::process_group::running(pid),
        "the stranger's planner {pid} outlived upm run"
    );
    let (sent, answered, refused) = log
        .lines()
        .find_map(|l| {
            let rest = l.strip_prefix("planner.py: sent ")?;
            let w: Vec<&str> = rest.split_whitespace().collect();
            Some((w[0].parse::<u64>().ok()?, w[2].parse::<u64>().ok()?, w[4].parse::<u64>().ok()?))
        })
        .unwrap_or_else(|| panic!("no final line in planner.log:\n{log}"));
    assert!(sent > 0 && answered > 0, "sent {sent}, answered {answered}:\n{log}");
    assert_eq!(refused, 0, "{log}");
    assert_eq!(m["core"]["rejected_requests"], 0, "{m}");
    assert_eq!(m["core"]["rejected_parts"], 0, "{m}");
    assert_eq!(m["clients"]["planner"]["restarts"], 0, "{m}\n{log}");
}
