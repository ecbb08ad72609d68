//! `upm bench hmi`: what the operator page costs the core. Real `upm run
//! feed --hmi` runs of the same length and seed, in alternating pairs:
//! the page served with nobody watching, and the page with
//! [`PAGE_CLIENTS`] WebSocket clients reading every update (what a browser
//! on the page receives; drawing happens on the browser's machine). The
//! figures: the core's motor wake-up and solver p99 of each run, their
//! medians and the ratio with/without, the page's updates received, and
//! the host with its load.

use std::net::TcpStream;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use anyhow::Context;
use serde_json::{Value, json};

/// Pages open in the "with" runs.
pub const PAGE_CLIENTS: usize = 10;
/// Each run's length by default, and with `--quick`.
pub const DEFAULT_SECONDS: f64 = 60.0;
pub const QUICK_SECONDS: f64 = 20.0;

#[derive(Debug, Clone)]
pub struct HmiBench {
    pub seconds: f64,
    pub rounds: usize,
    pub seed: u64,
}

/// What the clients of one run received.
#[derive(Debug, Default)]
struct Received {
    messages: AtomicU64,
    bytes: AtomicU64,
    /// Pages the server closed (it does when the run ends).
    closed: AtomicU64,
    /// Pages that could not connect, or whose connection broke.
    failed: AtomicU64,
}

/// A connection the other end dropped or reset.
fn gone(e: &tungstenite::Error) -> bool {
    use std::io::ErrorKind::{BrokenPipe, ConnectionAborted, ConnectionReset, UnexpectedEof};
    match e {
        tungstenite::Error::Io(e) => {
            matches!(e.kind(), BrokenPipe | ConnectionAborted | ConnectionReset | UnexpectedEof)
        }
        tungstenite::Error::Protocol(tungstenite::error::ProtocolError::ResetWithoutClosingHandshake) => true,
        _ => false,
    }
}

/// `clients` WebSocket readers of `url` until `stop`, each off `cpu`; a
/// page the server drops after `ending` counts as closed, not failed.
fn open_pages(
    url: &str,
    clients: usize,
    cpu: Option<usize>,
    stop: &Arc<AtomicBool>,
    ending: Instant,
) -> (Arc<Received>, Vec<std::thread::JoinHandle<()>>) {
    let received = Arc::new(Received::default());
    let threads = (0..clients)
        .map(|_| {
            let (url, stop, received) = (url.to_owned(), stop.clone(), received.clone());
            std::thread::spawn(move || {
                if let Some(c) = cpu {
                    let _ = rt_core::rt_setup::keep_current_thread_off(c);
                }
                let Ok((mut ws, _)) = tungstenite::connect(url.as_str()) else {
                    received.failed.fetch_add(1, Ordering::Relaxed);
                    return;
                };
                if let tungstenite::stream::MaybeTlsStream::Plain(s) = ws.get_ref() {
                    let _ = s.set_read_timeout(Some(Duration::from_millis(500)));
                }
                while !stop.load(Ordering::Relaxed) {
                    match ws.read() {
                        Ok(tungstenite::Message::Text(t)) => {
                            received.messages.fetch_add(1, Ordering::Relaxed);
                            received.bytes.fetch_add(t.len() as u64, Ordering::Relaxed);
                        }
                        Ok(tungstenite::Message::Close(_))
                        | Err(tungstenite::Error::ConnectionClosed | tungstenite::Error::AlreadyClosed) => {
                            received.closed.fetch_add(1, Ordering::Relaxed);
                            return;
                        }
                        Ok(_) => {}
                        Err(tungstenite::Error::Io(e)) if e.kind() == std::io::ErrorKind::WouldBlock => {}
                        Err(tungstenite::Error::Io(e)) if e.kind() == std::io::ErrorKind::TimedOut => {}
                        // The server went away without a close frame: at the
                        // run's end that is its stop, before it a failure.
                        Err(e) if gone(&e) && Instant::now() >= ending => {
                            received.closed.fetch_add(1, Ordering::Relaxed);
                            return;
                        }
                        Err(_) => {
                            received.failed.fetch_add(1, Ordering::Relaxed);
                            return;
                        }
                    }
                }
                let _ = ws.close(None);
            })
        })
        .collect();
    (received, threads)
}

/// One `upm run feed --hmi` run of `b.seconds`, with `clients` pages open.
fn one_run(
    b: &HmiBench,
    dir: &Path,
    name: &str,
    clients: usize,
    cpu: Option<usize>,
) -> anyhow::Result<Value> {
    let port = std::net::TcpListener::bind("127.0.0.1:0")?.local_addr()?.port();
    let prefix = format!("upm_bench_hmi_{}_{name}_", std::process::id());
    let out = dir.join(name);
    let upm = std::env::var_os("UPM_EXE")
        .map_or_else(|| std::env::current_exe().context("locating upm"), |p| Ok(p.into()))?;
    let mut child = Command::new(upm)
        .args(["run", "feed", "--quiet", "--no-record", "--prefix", &prefix])
        .args(["--duration", &b.seconds.to_string(), "--seed", &b.seed.to_string()])
        .args(["--hmi", &format!("127.0.0.1:{port}"), "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .context("starting upm run feed --hmi")?;
    let up = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        if let Some(s) = child.try_wait()? {
            anyhow::bail!("upm run feed --hmi ended at start-up ({s}); see {}", out.join("logs").display());
        }
        anyhow::ensure!(up.elapsed() < Duration::from_secs(60), "the page's server never came up");
        std::thread::sleep(Duration::from_millis(100));
    }
    let stop = Arc::new(AtomicBool::new(false));
    // The rig started before its page answered: it stops before `up + seconds`.
    let ending = up + Duration::from_secs_f64(0.75 * b.seconds);
    let (received, threads) = open_pages(&format!("ws://127.0.0.1:{port}/ws"), clients, cpu, &stop, ending);
    let o = child.wait_with_output()?;
    stop.store(true, Ordering::Relaxed);
    for t in threads {
        let _ = t.join();
    }
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    anyhow::ensure!(o.status.success(), "upm run feed --hmi failed: {}", String::from_utf8_lossy(&o.stderr));
    let m: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).context("metrics.json")?)?;
    Ok(json!({
        "pages": clients,
        "motor_p99_us": m["latency_us"]["motor_wakeup"]["p99"],
        "solver_p99_us": m["latency_us"]["solver"]["p99"],
        "overruns": m["core"]["overruns"],
        "ticks": m["core"]["ticks"],
        "hmi_restarts": m["clients"]["hmi"]["restarts"],
        "updates_received": received.messages.load(Ordering::Relaxed),
        "bytes_received": received.bytes.load(Ordering::Relaxed),
        "pages_closed_by_server": received.closed.load(Ordering::Relaxed),
        "pages_failed": received.failed.load(Ordering::Relaxed),
    }))
}

fn median(runs: &[Value], key: &str) -> Value {
    let mut v: Vec<f64> = runs.iter().filter_map(|r| r[key].as_f64()).collect();
    v.sort_by(f64::total_cmp);
    if v.is_empty() { Value::Null } else { json!(upm_stats::percentile(&v, 0.5)) }
}

fn ratio(a: &Value, b: &Value) -> Value {
    match (a.as_f64(), b.as_f64()) {
        (Some(a), Some(b)) if b > 0.0 => json!(a / b),
        _ => Value::Null,
    }
}

/// The 1-, 5- and 15-minute load averages.
fn load() -> Value {
    let text = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let v: Vec<f64> = text.split_whitespace().take(3).filter_map(|x| x.parse().ok()).collect();
    json!(v)
}

/// `b.rounds` pairs of runs, without and with pages, alternating.
pub fn run(b: &HmiBench) -> anyhow::Result<Value> {
    anyhow::ensure!(b.seconds.is_finite() && b.seconds >= 10.0, "each run must last at least 10 s");
    anyhow::ensure!(b.rounds >= 1, "at least one round");
    let config = upm_commands::scenario::Scenario::load(&upm_commands::scenario::resolve("feed"))?
        .config(b.seed, "unused_")?;
    let cpu = config.cpu_to_avoid();
    let dir = std::env::temp_dir().join(format!("upm_bench_hmi_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir)?;
    let load_before = load();
    let (mut without, mut with) = (Vec::new(), Vec::new());
    for r in 0..b.rounds {
        without.push(one_run(b, &dir, &format!("without_{r}"), 0, cpu)?);
        with.push(one_run(b, &dir, &format!("with_{r}"), PAGE_CLIENTS, cpu)?);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let summary = |runs: &[Value]| {
        json!({ "motor_p99_us_median": median(runs, "motor_p99_us"), "solver_p99_us_median": median(runs, "solver_p99_us"),
                "overruns_median": median(runs, "overruns") })
    };
    let (s0, s1) = (summary(&without), summary(&with));
    Ok(json!({
        "seconds_per_run": b.seconds,
        "rounds": b.rounds,
        "seed": b.seed,
        "pages": PAGE_CLIENTS,
        "without": s0,
        "with": s1,
        "ratio_motor_p99": ratio(&s1["motor_p99_us_median"], &s0["motor_p99_us_median"]),
        "ratio_solver_p99": ratio(&s1["solver_p99_us_median"], &s0["solver_p99_us_median"]),
        "runs": { "without": without, "with": with },
        "load_before": load_before,
        "load_after": load(),
        "host": upm_bench::host_facts::read_all(),
    }))
}

pub fn to_text(v: &Value) -> String {
    let f = |x: &Value| x.as_f64().map_or("—".to_owned(), |x| format!("{x:.2}"));
    let each = |k: &str, what: &str| -> String {
        v["runs"][k]
            .as_array()
            .map(|runs| runs.iter().map(|r| f(&r[what])).collect::<Vec<_>>().join(", "))
            .unwrap_or_default()
    };
    let updates: Vec<String> = v["runs"]["with"]
        .as_array()
        .map(|runs| {
            runs.iter().map(|r| format!("{} ({} failed)", r["updates_received"], r["pages_failed"])).collect()
        })
        .unwrap_or_default();
    format!(
        "{} rounds of {} s each, seed {}; {} pages open in the \"with\" runs\n\
         motor wake-up p99 µs: without pages {} (median {}), with {} (median {}): ratio {}\n\
         solver p99 µs: without pages {} (median {}), with {} (median {}): ratio {}\n\
         updates received by the pages per run: {}\n\
         load average before {}, after {}\n{}",
        v["rounds"],
        v["seconds_per_run"],
        v["seed"],
        v["pages"],
        each("without", "motor_p99_us"),
        f(&v["without"]["motor_p99_us_median"]),
        each("with", "motor_p99_us"),
        f(&v["with"]["motor_p99_us_median"]),
        f(&v["ratio_motor_p99"]),
        each("without", "solver_p99_us"),
        f(&v["without"]["solver_p99_us_median"]),
        each("with", "solver_p99_us"),
        f(&v["with"]["solver_p99_us_median"]),
        f(&v["ratio_solver_p99"]),
        updates.join(", "),
        v["load_before"],
        v["load_after"],
        upm_bench::host_facts::to_text(&v["host"])
    )
}
