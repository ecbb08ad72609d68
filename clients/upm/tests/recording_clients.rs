//! The flight recorder read by clients nobody in this project wrote: a real
//! `upm run` recording opened with the `mcap` package from PyPI (every
//! channel, the counts in the metadata, the attached config), the live view
//! of `upm run --monitor` read by Foxglove's own `@foxglove/ws-protocol`
//! client from npm, and `docs/foxglove-layout.json` checked against the
//! channels the recorder makes.
//!
//! What they need (a venv with `mcap`, the npm packages) is installed once
//! under target/tmp. The rig tests run one at a time (two cores on a small
//! machine would compete for the motor's CPU).

mod common;

use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Output, Stdio};
use std::sync::{Mutex, MutexGuard, OnceLock, PoisonError};
use std::time::{Duration, Instant};

use serde_json::Value;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
const SCRIPTS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/recording_clients");
const TMP: &str = env!("CARGO_TARGET_TMPDIR");

/// One rig at a time (see the module doc).
fn one_rig() -> MutexGuard<'static, ()> {
    static RIG: Mutex<()> = Mutex::new(());
    RIG.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A Python with the `mcap` package (the MCAP reader from PyPI).
fn mcap_python() -> PathBuf {
    static PY: OnceLock<PathBuf> = OnceLock::new();
    PY.get_or_init(|| common::venv("upm-mcap-python", "mcap", "mcap==1.6.0")).clone()
}

/// The Foxglove WebSocket client the live test uses.
#[derive(Debug, Clone)]
enum LiveClient {
    /// Foxglove's `@foxglove/ws-protocol` under node; the path is node_modules.
    Node(PathBuf),
    /// Our own Python speaking the protocol (no node/npm on this machine).
    Python(PathBuf),
}

fn has(tool: &str) -> bool {
    Command::new(tool).arg("--version").output().is_ok_and(|o| o.status.success())
}

/// `@foxglove/ws-protocol` and `ws` installed under target/tmp when node and
/// npm are on PATH (UPM_TEST_FOXGLOVE_CLIENT=python forces the fallback).
fn live_client() -> LiveClient {
    static CLIENT: OnceLock<LiveClient> = OnceLock::new();
    CLIENT
        .get_or_init(|| {
            let forced = std::env::var("UPM_TEST_FOXGLOVE_CLIENT").is_ok_and(|v| v == "python");
            if forced || !has("node") || !has("npm") {
                // Fallback: our own code (live_topic.py), not a stranger's client.
                eprintln!("recording_clients: the live test uses its own Python client (forced: {forced})");
                return LiveClient::Python(common::venv(
                    "upm-websockets-python",
                    "websockets",
                    "websockets>=13,<16",
                ));
            }
            let dir = Path::new(TMP).join("upm-foxglove-node");
            let modules = dir.join("node_modules");
            let resolves = || {
                Command::new("node")
                    .args(["-e", "require.resolve('@foxglove/ws-protocol'); require.resolve('ws')"])
                    .env("NODE_PATH", &modules)
                    .output()
                    .is_ok_and(|o| o.status.success())
            };
            if !resolves() {
                std::fs::create_dir_all(&dir).expect("node dir");
                common::run_ok(
                    Command::new("npm")
                        .args(["install", "--no-audit", "--no-fund", "--loglevel=error", "--prefix"])
                        .arg(&dir)
                        .args(["@foxglove/ws-protocol@0.8", "ws"]),
                );
            }
            assert!(resolves(), "@foxglove/ws-protocol not installed in {}", modules.display());
            LiveClient::Node(modules)
        })
        .clone()
}

/// A fresh output directory under target/tmp.
fn out_dir(tag: &str) -> PathBuf {
    let dir = Path::new(TMP).join(format!("recording_clients_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn python_mcap_reads_every_channel_of_a_real_run() {
    let py = mcap_python();
    let _rig = one_rig();
    let prefix = common::unique_prefix("rec_mcap");
    let out = out_dir("mcap");
    let started = Instant::now();
    let run = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["run", "sort", "--duration", "6", "--quiet", "--json", "--out"])
        .arg(&out)
        .args(["--prefix", &prefix])
        .current_dir(ROOT)
        .output()
        .expect("upm run");
    let run_s = started.elapsed().as_secs_f64();
    common::remove_prefix(&prefix);
    assert!(run.status.success(), "upm run: {}", text(&run.stderr));
    let metrics: Value = serde_json::from_slice(&run.stdout).expect("upm run prints metrics.json");
    let recording = &metrics["recording"];
    println!("upm run sort --duration 6: {run_s:.1} s; recording {recording}");
    assert_eq!(recording["recorder_exit_ok"], true, "{recording}");

    let mcap = out.join("run.mcap");
    assert!(mcap.is_file(), "no {}", mcap.display());
    let started = Instant::now();
    let check = Command::new(&py)
        .arg(Path::new(SCRIPTS).join("check_mcap.py"))
        .arg(&mcap)
        .arg(out.join("config.toml"))
        .arg(&prefix)
        .arg("sort")
        .output()
        .expect("python");
    println!("{}{}", text(&check.stdout), text(&check.stderr));
    println!("check_mcap.py: {:.2} s", started.elapsed().as_secs_f64());
    assert!(check.status.success(), "check_mcap.py failed on {} (left there)", mcap.display());
    let _ = std::fs::remove_dir_all(&out);
}

/// A free localhost port (free when this returns; a race is unlikely).
fn free_port() -> u16 {
    let l = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    l.local_addr().expect("addr").port()
}

/// A background `upm run`, stopped (SIGINT, then SIGKILL after 20 s) when
/// dropped or by [`Background::stop`].
#[derive(Debug)]
struct Background {
    child: Option<Child>,
}

impl Background {
    fn stop(&mut self) -> Option<(ExitStatus, Output)> {
        let mut child = self.child.take()?;
        if matches!(child.try_wait(), Ok(None)) {
            // SAFETY: kill(2) on the process this test started and has not reaped.
            unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
        }
        let asked = Instant::now();
        let status = loop {
            match child.try_wait() {
                Ok(Some(s)) => break s,
                Ok(None) if asked.elapsed() < Duration::from_secs(20) => {
                    std::thread::sleep(Duration::from_millis(20));
                }
                _ => {
                    let _ = child.kill();
                    break child.wait().expect("wait");
                }
            }
        };
        let mut o = Output { status, stdout: Vec::new(), stderr: Vec::new() };
        if let Some(mut s) = child.stdout.take() {
            let _ = s.read_to_end(&mut o.stdout);
        }
        if let Some(mut s) = child.stderr.take() {
            let _ = s.read_to_end(&mut o.stderr);
        }
        Some((status, o))
    }
}

impl Drop for Background {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Wait until the rig on `prefix` has published part states (seen by a
/// subscriber of our own), so the client's one second is not spent on the
/// rig starting up. Returns how long that took.
fn wait_for_part_states(prefix: &str, run: &mut Background, within: Duration) -> Duration {
    use ipc_types::{PartStates, WireMessage as _};
    let started = Instant::now();
    let exited =
        |run: &mut Background| run.child.as_mut().is_some_and(|c| c.try_wait().is_ok_and(|s| s.is_some()));
    // The core creates the services; subscribe only once it runs.
    while !ipc_types::discovery::core_running(prefix).unwrap_or(false) {
        assert!(!exited(run), "upm run exited at start-up: {:?}", run.stop());
        assert!(started.elapsed() < within, "no core on {prefix} within {within:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
    let node = common::plain_node(prefix);
    let sub = ipc_types::ports::subscriber::<PartStates>(&node, PartStates::SERVICE).expect("subscriber");
    loop {
        if sub.receive().expect("receive").is_some() {
            return started.elapsed();
        }
        assert!(!exited(run), "upm run exited at start-up: {:?}", run.stop());
        assert!(started.elapsed() < within, "no part states on {prefix} within {within:?}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn foxglove_client_receives_part_states_live() {
    let client = live_client();
    let _rig = one_rig();
    let port = free_port();
    let prefix = common::unique_prefix("rec_live");
    let out = out_dir("live");
    let started = Instant::now();
    let mut run = Background {
        child: Some(
            Command::new(env!("CARGO_BIN_EXE_upm"))
                .args(["run", "sort", "--duration", "12", "--quiet", "--monitor", &port.to_string()])
                .args(["--no-record", "--out"])
                .arg(&out)
                .args(["--prefix", &prefix])
                .current_dir(ROOT)
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .expect("upm run"),
        ),
    };
    let rig_up = wait_for_part_states(&prefix, &mut run, Duration::from_secs(20));
    println!("rig publishing part states {:.0} ms after `upm run`", rig_up.as_secs_f64() * 1e3);

    let url = format!("ws://127.0.0.1:{port}");
    let topic = format!("{}{}", ipc_types::service_names::PART_STATES, upm_recorder::JSON_SUFFIX);
    // The client retries connecting for up to 20 s and wants a message
    // within 1000 ms of subscribing.
    let args = [url.as_str(), topic.as_str(), "20", "1000"];
    let mut cmd = match &client {
        LiveClient::Node(modules) => {
            let mut c = Command::new("node");
            c.arg(Path::new(SCRIPTS).join("live_topic.js")).args(args).env("NODE_PATH", modules);
            c
        }
        LiveClient::Python(py) => {
            let mut c = Command::new(py);
            c.arg(Path::new(SCRIPTS).join("live_topic.py")).args(args);
            c
        }
    };
    let client_started = Instant::now();
    let live = cmd.output().expect("client");
    let client_s = client_started.elapsed().as_secs_f64();
    let still_running = run.child.as_mut().is_some_and(|c| matches!(c.try_wait(), Ok(None)));
    let (status, o) = run.stop().expect("stopped once");
    println!(
        "upm run stopped by SIGINT after {:.1} s ({status}); still running when the client finished: {still_running}",
        started.elapsed().as_secs_f64()
    );
    common::remove_prefix(&prefix);
    println!("client {client:?} ({client_s:.2} s):\n{}{}", text(&live.stdout), text(&live.stderr));
    assert!(live.status.success(), "the Foxglove client got nothing; upm run said:\n{}", text(&o.stderr));
    let first_ms: f64 = text(&live.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("first message after ")?.strip_suffix(" ms")?.parse().ok())
        .expect("the client prints the time to its first message");
    println!("time to first {topic} message after subscribing: {first_ms:.1} ms");
    assert!(first_ms <= 1000.0);
    assert!(still_running, "the run ended before the client was done: {}", text(&o.stderr));
    assert!(text(&o.stderr).contains(&url), "upm run does not name {url}: {}", text(&o.stderr));
    // --no-record: served, not written.
    assert!(!out.join("run.mcap").exists(), "--no-record wrote {}", out.join("run.mcap").display());
    let _ = std::fs::remove_dir_all(&out);
}

/// The JSON schema of a `/json` topic or `upm/latency`, as the recorder makes it.
fn schema_of_topic(topic: &str) -> Option<Value> {
    use ipc_types::{
        CoreCommand, ExplicitSchedule, FeedStatus, ForceRequest, FrameHeader, LineStatus, PartStates,
        PickCommand, RecipeCommand, Rejection, RigInfo, Schedule, Telemetry, service_names as s,
    };
    use upm_recorder::decoded::{latencies, schema, schema_of};
    if topic == upm_recorder::LATENCY_TOPIC {
        return Some(schema_of(&latencies(&Telemetry::new())));
    }
    Some(match topic.strip_suffix(upm_recorder::JSON_SUFFIX)? {
        s::PART_STATES | s::SIM_GROUND_TRUTH => schema::<PartStates>(),
        s::FORCE_REQUEST => schema::<ForceRequest>(),
        s::EXPLICIT_SCHEDULE => schema::<ExplicitSchedule>(),
        s::CORE_COMMAND => schema::<CoreCommand>(),
        s::SCHEDULE => schema::<Schedule>(),
        s::TELEMETRY => schema::<Telemetry>(),
        s::REJECTION => schema::<Rejection>(),
        s::RIG_INFO => schema::<RigInfo>(),
        s::FEED => schema::<FeedStatus>(),
        s::PICK => schema::<PickCommand>(),
        s::RECIPE | s::RECIPE_ACTIVE => schema::<RecipeCommand>(),
        s::LINE => schema::<LineStatus>(),
        s::CAMERA_FRAME => schema::<FrameHeader>(),
        _ => return None,
    })
}

/// The panel ids in a layout tree (a panel id, or a split of two trees).
fn panels_in(tree: &Value, ids: &mut Vec<String>) {
    match tree {
        Value::String(id) => ids.push(id.clone()),
        Value::Object(split) => {
            assert!(
                matches!(split.get("direction").and_then(Value::as_str), Some("row" | "column")),
                "a split without direction row/column: {tree}"
            );
            if let Some(p) = split.get("splitPercentage") {
                assert!(p.as_f64().is_some_and(|p| (0.0..=100.0).contains(&p)), "splitPercentage {p}");
            }
            panels_in(&split["first"], ids);
            panels_in(&split["second"], ids);
        }
        _ => panic!("not a layout tree: {tree}"),
    }
}

/// `docs/foxglove-layout.json` is a Foxglove layout whose panels show
/// topics and fields the recorder makes (checked against its schemas, so a
/// renamed field breaks this test, not the user's dashboard).
#[test]
fn foxglove_layout_shows_the_recorders_channels() {
    let path = Path::new(ROOT).join("docs/foxglove-layout.json");
    let layout: Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("docs/foxglove-layout.json"))
            .expect("docs/foxglove-layout.json is JSON");
    for key in ["configById", "layout", "globalVariables", "userNodes", "playbackConfig"] {
        assert!(!layout[key].is_null(), "the layout lacks {key}");
    }
    let configs = layout["configById"].as_object().expect("configById");
    let mut ids = Vec::new();
    panels_in(&layout["layout"], &mut ids);
    let mut sorted = ids.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), ids.len(), "a panel twice in the tree: {ids:?}");
    let mut keys: Vec<_> = configs.keys().cloned().collect();
    keys.sort();
    assert_eq!(sorted, keys, "the tree's panels and configById differ");

    let of_kind = |kind: &str| -> Vec<&Value> {
        configs.iter().filter(|(id, _)| id.split('!').next() == Some(kind)).map(|(_, c)| c).collect()
    };
    let three_d = of_kind("3D");
    assert_eq!(three_d.len(), 1, "one 3D panel");
    assert_eq!(three_d[0]["topics"][upm_recorder::SCENE_TOPIC]["visible"], true, "{}", three_d[0]);
    assert_eq!(three_d[0]["followTf"], "plate", "the scene's entities are in frame plate");

    // Every plotted path and the raw messages' topic, against the schemas.
    let mut paths: Vec<String> = of_kind("Plot")
        .iter()
        .flat_map(|c| c["paths"].as_array().expect("Plot paths").iter())
        .map(|p| {
            assert_eq!(p["enabled"], true, "{p}");
            p["value"].as_str().expect("path value").to_owned()
        })
        .collect();
    let raw = of_kind("RawMessages");
    assert_eq!(raw.len(), 1, "one Raw Messages panel");
    let raw_topic = raw[0]["topicPath"].as_str().expect("topicPath").to_owned();
    assert_eq!(raw_topic, format!("{}{}", ipc_types::service_names::TELEMETRY, upm_recorder::JSON_SUFFIX));
    paths.push(raw_topic);
    for want in ["upm/latency.motor_wakeup.p99_us", "upm/latency.solver.p99_us", "upm/schedule/json.residual"]
    {
        assert!(paths.iter().any(|p| p == want), "no plot of {want}: {paths:?}");
    }
    for path in &paths {
        let mut fields = path.split('.');
        let topic = fields.next().expect("topic");
        let mut at = schema_of_topic(topic).unwrap_or_else(|| panic!("{path}: the recorder has no {topic}"));
        for field in fields {
            at = at["properties"][field].clone();
            assert!(!at.is_null(), "{path}: no field {field} in {topic}'s schema");
        }
        if path.contains('.') {
            // A float may be null (∞ or NaN in JSON), never a string.
            let is_number = |t: &serde_json::Value| matches!(t.as_str(), Some("number" | "integer"));
            let types = at["type"].as_array().cloned().unwrap_or_else(|| vec![at["type"].clone()]);
            assert!(types.iter().any(is_number), "{path} is not a number: {at}");
        }
        println!("layout: {path} ok");
    }
}
