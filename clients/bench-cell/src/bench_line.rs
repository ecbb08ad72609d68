//! `upm bench line`: a robot on OPC UA against the simulator's own robot.
//! Three real `upm run feed` runs of the same length and seed: (A) the
//! robot outside (`--robot external`), a client written here with
//! async-opcua's client that subscribes to every pose's `Ready` and
//! `PartId` and calls `Picked` as a user; (B) the simulator's robot
//! (`--robot builtin`, no line); (C) as A while 200 clients connect and
//! drop (anonymous OPC UA sessions and Modbus TCP reads). Figures: picks of
//! A against B; `Picked`'s round trip; a part turning ready on the core's
//! `upm/feed` (this process subscribes over iceoryx2) to `Ready` reaching
//! the robot; the core's motor p99 of C against A (and B). The robot, like
//! the simulator's, is busy for the recipe's `pick_s` after each pick.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::Context;
use iceoryx2::prelude::*;
use ipc_types::{FeedStatus, monotonic_now_ns, service_names};
use opcua::client::{ClientBuilder, DataChangeCallback, IdentityToken, MonitoredItem, Password, Session};
use opcua::crypto::SecurityPolicy;
use opcua::types::{
    DataValue, MessageSecurityMode, MonitoredItemCreateRequest, NodeId, ReadValueId, TimestampsToReturn,
    UserTokenPolicy, Variant,
};
use serde_json::{Value, json};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use upm_commands::scenario::{Scenario, resolve};

/// What to run.
#[derive(Debug, Clone)]
pub struct LineBench {
    /// Each run's length (simulated seconds, real time).
    pub seconds: f64,
    pub seed: u64,
    /// Clients that connect and drop during run C (half OPC UA, half
    /// Modbus), and C's length (`seconds` but with `--quick`).
    pub churn: usize,
    pub churn_seconds: f64,
}

/// Each run's length by default: three runs stay within 5 minutes.
pub const DEFAULT_SECONDS: f64 = 90.0;
/// `--quick`: long enough for the first parts to reach their poses (C: 20 s).
pub const QUICK_SECONDS: f64 = 55.0;
const USER: &str = "robot";
const PASSWORD: &str = "bench-line-robot";
/// The target for a part turning ready → `Ready` at the robot, p99.
const READY_TARGET_MS: f64 = 50.0;

/// Part turned ready, first seen on `upm/feed`: (pose, part) → (received, status stamp), ns.
type ReadySeen = HashMap<(u32, u32), (u64, u64)>;

fn ms(ns: u64) -> f64 {
    ns as f64 / 1e6
}

/// p50, p99 and max of `v` (ms).
fn summary(mut v: Vec<f64>) -> Value {
    v.sort_by(f64::total_cmp);
    let p = |q| upm_stats::percentile(&v, q);
    json!({"samples": v.len(), "p50_ms": p(0.5), "p99_ms": p(0.99), "max_ms": v.last()})
}

/// Subscribes to the core's `upm/feed` from a thread off the motor's CPU;
/// notes when each (pose, part) is first ready.
fn watch_feed(
    prefix: String,
    cpu: Option<usize>,
    stop: Arc<AtomicBool>,
) -> std::thread::JoinHandle<ReadySeen> {
    std::thread::spawn(move || {
        if let Some(c) = cpu {
            let _ = rt_core::rt_setup::keep_current_thread_off(c);
        }
        let mut seen = ReadySeen::new();
        let node =
            ipc_types::rig_node::rig_node(&prefix, Some("upm-bench-line"), SignalHandlingMode::Disabled);
        let Ok(node) = node else { return seen };
        let Ok(feed) = ipc_types::ports::subscriber::<FeedStatus>(&node, service_names::FEED) else {
            return seen;
        };
        while !stop.load(Ordering::Relaxed) {
            while let Ok(Some(s)) = feed.receive() {
                let (now, f) = (monotonic_now_ns(), s.payload());
                for (n, p) in f.poses.iter().take(f.count as usize).enumerate() {
                    if p.ready != 0 && p.part_id != 0 {
                        seen.entry((n as u32, p.part_id)).or_insert((now, f.stamp_ns));
                    }
                }
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        seen
    })
}

/// An OPC UA session on the security-None endpoint, connected.
async fn open_session(url: &str, who: IdentityToken, pki: &Path) -> anyhow::Result<(Arc<Session>, Loop)> {
    let mut client = ClientBuilder::new()
        .application_name("upm bench line")
        .application_uri("urn:upm:bench:line")
        .product_uri("urn:upm:bench")
        .pki_dir(pki)
        .create_sample_keypair(false)
        .trust_server_certs(true)
        .session_retry_limit(0)
        // The client's own floor is 100 ms: let the server's (10 ms) decide.
        .min_publish_interval(Duration::from_millis(1))
        .client()
        .map_err(|e| anyhow::anyhow!("OPC UA client config: {e:?}"))?;
    let endpoint =
        (url, SecurityPolicy::None.to_str(), MessageSecurityMode::None, UserTokenPolicy::anonymous());
    let (session, event_loop) = client.connect_to_matching_endpoint(endpoint, who).await?;
    let handle = Loop(event_loop.spawn());
    let up = tokio::time::timeout(Duration::from_secs(10), session.wait_for_connection()).await;
    if !up.unwrap_or(false) {
        anyhow::bail!("no session with {url}");
    }
    Ok((session, handle))
}

/// A session's event loop, stopped when dropped.
struct Loop(tokio::task::JoinHandle<opcua::types::StatusCode>);

impl Drop for Loop {
    fn drop(&mut self) {
        self.0.abort();
    }
}

async fn close(session: Arc<Session>, _event_loop: Loop) {
    let _ = tokio::time::timeout(Duration::from_secs(2), session.disconnect()).await;
}

async fn read_one(session: &Session, node: NodeId) -> anyhow::Result<DataValue> {
    let v = session.read(&[ReadValueId::from(node)], TimestampsToReturn::Neither, 0.0).await?;
    v.into_iter().next().ok_or_else(|| anyhow::anyhow!("an empty read"))
}

/// What the robot saw and did.
#[derive(Debug, Default)]
struct RobotLog {
    /// (pose, part) → when `Ready` = true for that part reached the robot, ns.
    ready_at: HashMap<(u32, u32), u64>,
    /// `Picked` round trips of accepted calls, ms; refusals by status.
    rtt_ms: Vec<f64>,
    refused: HashMap<String, u64>,
    /// Arrivals of `PartsPerMinute` changes (it changes with every status).
    rate_arrivals: Vec<u64>,
    revised_publishing_ms: Option<f64>,
    revised_sampling_ms: Vec<f64>,
    poses: u32,
}

/// One notification: (pose or `u32::MAX` for the rate, is `Ready`, value, arrival ns).
type Change = (u32, bool, Variant, u64);

/// The robot: a user session, a subscription to every pose, a pick as soon
/// as a pose is ready and the robot free, until `stop`.
async fn robot(url: String, pki: PathBuf, pick_s: f64, stop: Arc<AtomicBool>) -> anyhow::Result<RobotLog> {
    let who = IdentityToken::UserName(USER.into(), Password::new(PASSWORD));
    let (session, event_loop) = open_session(&url, who, &pki).await?;
    let ns = session.get_namespace_index("urn:upm:rig").await?;
    let id = |s: &str| NodeId::new(ns, s.to_owned());
    let mut log = RobotLog::default();
    // The pose nodes appear with the cell's first status.
    let found = Instant::now();
    loop {
        let ready = |n: u32| read_one(&session, id(&format!("Rig.Pick.{n}.Ready")));
        while log.poses < 16 && ready(log.poses).await?.status.is_none_or(|s| s.is_good()) {
            log.poses += 1;
        }
        if log.poses > 0 {
            break;
        }
        anyhow::ensure!(found.elapsed() < Duration::from_secs(30), "no pick pose appeared on {url}");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let (tx, mut rx) = tokio::sync::mpsc::unbounded_channel::<Change>();
    let mut items: Vec<(NodeId, (u32, bool))> = vec![(id("Rig.PartsPerMinute"), (u32::MAX, false))];
    for n in 0..log.poses {
        items.push((id(&format!("Rig.Pick.{n}.Ready")), (n, true)));
        items.push((id(&format!("Rig.Pick.{n}.PartId")), (n, false)));
    }
    let which: HashMap<NodeId, (u32, bool)> = items.iter().cloned().collect();
    let callback = DataChangeCallback::new(move |dv: DataValue, item: &MonitoredItem| {
        let t = monotonic_now_ns();
        if let (Some(&(n, ready)), Some(v)) = (which.get(&item.item_to_monitor().node_id), dv.value) {
            let _ = tx.send((n, ready, v, t));
        }
    });
    // 0 ms: the fastest each interval the server allows.
    let sub = session.create_subscription(Duration::ZERO, 3000, 30, 0, 0, true, callback).await?;
    log.revised_publishing_ms =
        session.subscription_state().lock().get(sub).map(|s| s.publishing_interval().as_secs_f64() * 1e3);
    let requests = items
        .iter()
        .map(|(node, _)| {
            let mut r = MonitoredItemCreateRequest::from(node.clone());
            (r.requested_parameters.sampling_interval, r.requested_parameters.queue_size) = (0.0, 10);
            r
        })
        .collect();
    for c in session.create_monitored_items(sub, TimestampsToReturn::Neither, requests).await? {
        log.revised_sampling_ms.push(c.result.revised_sampling_interval);
    }
    let (rig, picked) = (id("Rig"), id("Rig.PickedMethod"));
    let mut poses = vec![(false, 0u32); log.poses as usize];
    // The part last called for at each pose; a refused one is tried again
    // after 100 ms while it reads ready.
    let (mut taken, mut retry_at) = (vec![0u32; poses.len()], vec![Instant::now(); poses.len()]);
    let mut free_at = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        let wait = free_at.saturating_duration_since(Instant::now()).max(Duration::from_millis(20));
        if let Ok(Some((n, ready, v, t))) = tokio::time::timeout(wait, rx.recv()).await {
            let Some(p) = poses.get_mut(n as usize) else {
                log.rate_arrivals.push(t);
                continue;
            };
            match (ready, v) {
                (true, Variant::Boolean(b)) => p.0 = b,
                (false, Variant::UInt32(part)) => p.1 = part,
                _ => {}
            }
            if p.0 && p.1 != 0 {
                log.ready_at.entry((n, p.1)).or_insert(t);
            }
        }
        // Every notification waiting is taken before a pick.
        if !rx.is_empty() || Instant::now() < free_at {
            continue;
        }
        let now = Instant::now();
        let want = |n: usize| poses[n].0 && poses[n].1 != 0 && taken[n] != poses[n].1 && now >= retry_at[n];
        let Some(n) = (0..poses.len()).find(|&n| want(n)) else { continue };
        taken[n] = poses[n].1;
        let args = Some(vec![Variant::UInt32(n as u32)]);
        let t0 = Instant::now();
        let r = session.call_one((rig.clone(), picked.clone(), args)).await;
        let rtt = t0.elapsed().as_secs_f64() * 1e3;
        match r.map(|r| r.status_code) {
            Ok(s) if s.is_good() => {
                log.rtt_ms.push(rtt);
                free_at = Instant::now() + Duration::from_secs_f64(pick_s);
            }
            other => {
                let code = other.unwrap_or_else(|e| e.status());
                *log.refused.entry(format!("{code}")).or_default() += 1;
                (taken[n], retry_at[n]) = (0, Instant::now() + Duration::from_millis(100));
            }
        }
    }
    close(session, event_loop).await;
    Ok(log)
}

/// One Modbus TCP client: connect, read input registers 0–7, close.
/// Returns register 0 (the state).
async fn modbus_read(addr: &str) -> anyhow::Result<u16> {
    let io = async {
        let mut s = tokio::net::TcpStream::connect(addr).await?;
        s.write_all(&[0, 1, 0, 0, 0, 6, 1, 4, 0, 0, 0, 8]).await?;
        let mut answer = [0u8; 25];
        s.read_exact(&mut answer).await?;
        anyhow::ensure!(answer[7] == 4 && answer[8] == 16, "a Modbus exception or short answer: {answer:?}");
        Ok(u16::from_be_bytes([answer[9], answer[10]]))
    };
    tokio::time::timeout(Duration::from_secs(5), io).await?
}

/// One anonymous OPC UA session: open, read `Rig.State`, close.
async fn opcua_read_state(url: &str, pki: &Path) -> anyhow::Result<String> {
    let (session, event_loop) = open_session(url, IdentityToken::Anonymous, pki).await?;
    let ns = session.get_namespace_index("urn:upm:rig").await?;
    let v = read_one(&session, NodeId::new(ns, "Rig.State")).await;
    close(session, event_loop).await;
    match v?.value {
        Some(Variant::String(s)) => Ok(s.to_string()),
        other => anyhow::bail!("Rig.State read {other:?}"),
    }
}

/// `clients` connect-and-drop clients in waves of 10 (half OPC UA, half
/// Modbus) spread over `span`, then one of each to see the servers are up.
async fn churn(url: String, modbus: String, pki: PathBuf, clients: usize, span: Duration) -> Value {
    let waves = clients.div_ceil(10).max(1);
    let (mut ok, mut failed) = ([0u64; 2], [0u64; 2]);
    let mut errors = Vec::new();
    let t0 = Instant::now();
    for w in 0..waves {
        tokio::time::sleep_until((t0 + span.mul_f64(w as f64 / waves as f64)).into()).await;
        let mut set = tokio::task::JoinSet::new();
        for i in (w * 10)..((w + 1) * 10).min(clients) {
            let (url, modbus, pki) = (url.clone(), modbus.clone(), pki.clone());
            set.spawn(async move {
                let kind = i % 2;
                let r = if kind == 0 {
                    opcua_read_state(&url, &pki).await.map(drop)
                } else {
                    modbus_read(&modbus).await.map(drop)
                };
                (kind, r)
            });
        }
        while let Some(Ok((kind, r))) = set.join_next().await {
            match r {
                Ok(()) => ok[kind] += 1,
                Err(e) => {
                    failed[kind] += 1;
                    errors.push(format!("{e:#}"));
                }
            }
        }
    }
    let took = t0.elapsed().as_secs_f64();
    let state = opcua_read_state(&url, &pki).await.unwrap_or_else(|e| format!("error: {e:#}"));
    let register = modbus_read(&modbus).await.map_or_else(|e| json!(format!("error: {e:#}")), |s| json!(s));
    errors.truncate(3);
    json!({"clients": clients, "seconds": took, "opcua_ok": ok[0], "opcua_failed": failed[0],
           "modbus_ok": ok[1], "modbus_failed": failed[1], "first_errors": errors,
           "after": {"opcua_state": state, "modbus_state": register}})
}

/// A free localhost port.
fn free_port() -> anyhow::Result<u16> {
    Ok(std::net::TcpListener::bind("127.0.0.1:0")?.local_addr()?.port())
}

/// The `upm` binary (`UPM_EXE` to use another build), as `upm run` finds it.
fn upm_exe() -> anyhow::Result<PathBuf> {
    std::env::var_os("UPM_EXE")
        .map_or_else(|| std::env::current_exe().context("locating upm"), |p| Ok(p.into()))
}

/// Start `upm run feed`; with `line`, the robot outside on these ports.
fn start_run(
    b: &LineBench,
    seconds: f64,
    out: &Path,
    prefix: &str,
    line: Option<(u16, u16, &Path)>,
) -> anyhow::Result<Child> {
    let mut c = Command::new(upm_exe()?);
    c.args(["run", "feed", "--quiet", "--no-record", "--prefix", prefix])
        .args(["--duration", &seconds.to_string(), "--seed", &b.seed.to_string(), "--out"])
        .arg(out);
    if let Some((opcua, modbus, users)) = line {
        c.args(["--robot", "external", "--opcua", &format!("127.0.0.1:{opcua}")])
            .args(["--modbus", &format!("127.0.0.1:{modbus}"), "--users"])
            .arg(users);
    } else {
        c.args(["--robot", "builtin"]);
    }
    c.stdout(Stdio::null()).stderr(Stdio::piped()).spawn().context("starting upm run")
}

/// Wait for the run to end; its metrics.json.
fn finish(child: Child, out: &Path, prefix: &str) -> anyhow::Result<Value> {
    let o = child.wait_with_output()?;
    ipc_types::rig_node::remove_prefix_segment(prefix);
    anyhow::ensure!(o.status.success(), "upm run feed failed: {}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("metrics.json")).context("metrics.json")?;
    Ok(serde_json::from_str(&text)?)
}

/// What one run with the robot outside gave.
struct External {
    metrics: Value,
    robot: RobotLog,
    feed: ReadySeen,
    churn: Value,
}

/// A run with the robot outside (and `churn` clients during it).
fn external_run(
    b: &LineBench,
    rt: &tokio::runtime::Runtime,
    dir: &Path,
    name: &str,
    churn_clients: usize,
    pick_s: f64,
    cpu: Option<usize>,
) -> anyhow::Result<External> {
    let (opcua, modbus) = (free_port()?, free_port()?);
    let prefix = format!("upm_bench_line_{}_{name}_", std::process::id());
    let out = dir.join(name);
    let seconds = if churn_clients > 0 { b.churn_seconds } else { b.seconds };
    let mut child = start_run(b, seconds, &out, &prefix, Some((opcua, modbus, &dir.join("users.toml"))))?;
    let up = Instant::now();
    while std::net::TcpStream::connect(("127.0.0.1", opcua)).is_err() {
        if let Some(s) = child.try_wait()? {
            anyhow::bail!("upm run feed ended at start-up ({s}); see {}", out.join("logs").display());
        }
        anyhow::ensure!(up.elapsed() < Duration::from_secs(60), "the line's OPC UA server never came up");
        std::thread::sleep(Duration::from_millis(100));
    }
    let stop = Arc::new(AtomicBool::new(false));
    let feed = watch_feed(prefix.clone(), cpu, stop.clone());
    let url = format!("opc.tcp://127.0.0.1:{opcua}/");
    let robot = rt.spawn(robot(url.clone(), dir.join("pki"), pick_s, stop.clone()));
    let span = Duration::from_secs_f64(seconds * 0.6);
    let churned = (churn_clients > 0)
        .then(|| rt.spawn(churn(url, format!("127.0.0.1:{modbus}"), dir.join("pki"), churn_clients, span)));
    // The robot picks until the run ends.
    while matches!(child.try_wait(), Ok(None)) && !robot.is_finished() {
        std::thread::sleep(Duration::from_millis(100));
    }
    let churn = churned.map_or(Ok(Value::Null), |h| rt.block_on(h))?;
    let metrics = finish(child, &out, &prefix);
    stop.store(true, Ordering::Relaxed);
    let robot = rt.block_on(robot)??;
    let feed = feed.join().map_err(|_| anyhow::anyhow!("the upm/feed watcher panicked"))?;
    ipc_types::rig_node::remove_prefix_segment(&prefix); // the watcher's node held it
    Ok(External { metrics: metrics?, robot, feed, churn })
}

fn motor_p99(m: &Value) -> Value {
    m["latency_us"]["motor_wakeup"]["p99"].clone()
}

/// Picks and rate of a run.
fn feed_of(m: &Value) -> Value {
    json!({"picked": m["feed"]["picked"], "parts_per_minute": m["feed"]["parts_per_minute"],
           "arrived": m["feed"]["arrived"], "lost": m["feed"]["lost"],
           "motor_p99_us": motor_p99(m), "overruns": m["core"]["overruns"], "ticks": m["core"]["ticks"],
           "pm_qos_held": m["core"]["pm_qos_held"]})
}

fn ratio(a: &Value, b: &Value) -> Value {
    match (a.as_f64(), b.as_f64()) {
        (Some(a), Some(b)) if b > 0.0 => json!(a / b),
        _ => Value::Null,
    }
}

/// Ready on `upm/feed` → `Ready` at the robot, per part both saw.
fn ready_latency(a: &External) -> Value {
    let (mut from_recv, mut from_stamp) = (Vec::new(), Vec::new());
    for (key, &at) in &a.robot.ready_at {
        if let Some(&(recv, stamp)) = a.feed.get(key) {
            from_recv.push(ms(at.saturating_sub(recv)));
            from_stamp.push(ms(at.saturating_sub(stamp)));
        }
    }
    let matched = from_recv.len();
    // A publish response brings every queued change at once: its
    // deliveries are arrivals more than 2 ms after the one before.
    let arrivals = &a.robot.rate_arrivals;
    let starts: Vec<u64> = arrivals
        .iter()
        .enumerate()
        .filter(|&(i, &t)| i == 0 || t.saturating_sub(arrivals[i - 1]) > 2_000_000)
        .map(|(_, &t)| t)
        .collect();
    let mut gaps: Vec<f64> = starts.windows(2).map(|w| ms(w[1] - w[0])).collect();
    gaps.sort_by(f64::total_cmp);
    from_recv.sort_by(f64::total_cmp);
    let recv = summary(from_recv.clone());
    json!({
        "from_feed_received": recv, "from_status_stamp": summary(from_stamp),
        "from_feed_received_each_ms": from_recv,
        "target_p99_ms": READY_TARGET_MS, "met": recv["p99_ms"].as_f64().map(|p| p <= READY_TARGET_MS),
        "ready_on_feed": a.feed.len(), "ready_at_robot": a.robot.ready_at.len(), "matched": matched,
        "revised_publishing_interval_ms": a.robot.revised_publishing_ms,
        "revised_sampling_interval_ms": a.robot.revised_sampling_ms.first(),
        "rate_changes": arrivals.len(), "rate_deliveries": starts.len(),
        "rate_delivery_gap_p50_ms": upm_stats::percentile(&gaps, 0.5),
        "rate_delivery_gap_min_ms": gaps.first(),
    })
}

/// Runs A, B and C; the figures.
pub fn run(b: &LineBench) -> anyhow::Result<Value> {
    anyhow::ensure!(b.seconds.is_finite() && b.seconds >= 10.0, "each run must last at least 10 s");
    let sc = Scenario::load(&resolve("feed"))?;
    let config = sc.config(b.seed, "unused_")?;
    let pick_s = config.feed_recipe("feed")?.map_or(1.0, |r| r.robot.pick_s);
    let cpu = config.cpu_to_avoid();
    let dir = std::env::temp_dir().join(format!("upm_bench_line_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir)?;
    upm_users::add_user(&dir.join("users.toml"), USER, PASSWORD)?;
    // The robot and the clients stay off the motor's CPU, as every client
    // of a rig does; `upm run` itself starts from this (unpinned) thread.
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .on_thread_start(move || {
            if let Some(c) = cpu {
                let _ = rt_core::rt_setup::keep_current_thread_off(c);
            }
        })
        .build()?;
    let a = external_run(b, &rt, &dir, "external", 0, pick_s, cpu)?;
    let out = dir.join("builtin");
    let prefix = format!("upm_bench_line_{}_builtin_", std::process::id());
    let builtin = finish(start_run(b, b.seconds, &out, &prefix, None)?, &out, &prefix)?;
    let c = external_run(b, &rt, &dir, "churn", b.churn, pick_s, cpu)?;
    let (ext, own, churned) = (feed_of(&a.metrics), feed_of(&builtin), feed_of(&c.metrics));
    let mut refused: Vec<String> = a.robot.refused.iter().map(|(k, n)| format!("{k} {n}")).collect();
    refused.sort();
    let v = json!({
        "seconds_per_run": b.seconds,
        "seed": b.seed,
        "robot_pick_s": pick_s,
        "poses": a.robot.poses,
        "throughput": {
            "external": ext, "builtin": own,
            "ratio_picked": ratio(&ext["picked"], &own["picked"]),
            "ratio_parts_per_minute": ratio(&ext["parts_per_minute"], &own["parts_per_minute"]),
            "target_ratio": 0.9,
        },
        "picked_call": {"round_trip": summary(a.robot.rtt_ms.clone()), "refused": refused},
        "ready": ready_latency(&a),
        "churn": {"run": churned, "without": {"motor_p99_us": ext["motor_p99_us"], "overruns": ext["overruns"]},
                  "no_line": {"motor_p99_us": own["motor_p99_us"], "overruns": own["overruns"]},
                  "clients": c.churn, "robot_picks_accepted": c.robot.rtt_ms.len(),
                  "line_restarts": c.metrics["clients"]["line"]["restarts"]},
        "host": upm_bench::host_facts::read_all(),
    });
    drop(rt);
    let _ = std::fs::remove_dir_all(&dir);
    Ok(v)
}

pub fn to_text(v: &Value) -> String {
    let f = |x: &Value| x.as_f64().map_or("—".to_owned(), |x| format!("{x:.2}"));
    let (t, r, c) = (&v["throughput"], &v["ready"], &v["churn"]);
    let rtt = &v["picked_call"]["round_trip"];
    let (rr, rs) = (&r["from_feed_received"], &r["from_status_stamp"]);
    format!(
        "{} s per run, seed {}, robot busy {} s a pick\n\
         picked: OPC UA robot {} ({} parts/min), simulator's robot {} ({} parts/min): ratio {} (target ≥ 0.9)\n\
         Picked round trip: p50 {} ms, p99 {} ms, max {} ms ({} calls; refused {})\n\
         ready on upm/feed → Ready at the robot: p50 {} ms, p99 {} ms, max {} ms ({} parts; target p99 ≤ 50 ms); \
         from the status stamp p50 {} / p99 {} ms\n\
         revised publishing {} ms, sampling {} ms; PartsPerMinute: {} changes in {} deliveries, {} ms apart (median)\n\
         {} connect-and-drop clients: motor p99 {} µs against {} µs without ({} µs with no line); \
         OPC UA {} ok {} failed, Modbus {} ok {} failed; after: State {}, register 0 = {}\n{}",
        v["seconds_per_run"],
        v["seed"],
        v["robot_pick_s"],
        t["external"]["picked"],
        f(&t["external"]["parts_per_minute"]),
        t["builtin"]["picked"],
        f(&t["builtin"]["parts_per_minute"]),
        f(&t["ratio_picked"]),
        f(&rtt["p50_ms"]),
        f(&rtt["p99_ms"]),
        f(&rtt["max_ms"]),
        rtt["samples"],
        v["picked_call"]["refused"],
        f(&rr["p50_ms"]),
        f(&rr["p99_ms"]),
        f(&rr["max_ms"]),
        rr["samples"],
        f(&rs["p50_ms"]),
        f(&rs["p99_ms"]),
        f(&r["revised_publishing_interval_ms"]),
        f(&r["revised_sampling_interval_ms"]),
        r["rate_changes"],
        r["rate_deliveries"],
        f(&r["rate_delivery_gap_p50_ms"]),
        c["clients"]["clients"],
        f(&c["run"]["motor_p99_us"]),
        f(&c["without"]["motor_p99_us"]),
        f(&c["no_line"]["motor_p99_us"]),
        c["clients"]["opcua_ok"],
        c["clients"]["opcua_failed"],
        c["clients"]["modbus_ok"],
        c["clients"]["modbus_failed"],
        c["clients"]["after"]["opcua_state"],
        c["clients"]["after"]["modbus_state"],
        upm_bench::host_facts::to_text(&v["host"])
    )
}
