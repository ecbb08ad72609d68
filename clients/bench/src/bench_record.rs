//! `upm bench record`: what the flight recorder and the live view cost.
//! Real multi-process `sort` runs, rotating without, with the recorder, with
//! the recorder and the monitor watched by a Foxglove client showing
//! docs/foxglove-layout.json's topics, and by one subscribed to every
//! channel (raw bytes included), compare the core's motor wake-up and
//! solver p99; the
//! spread of the runs without is the run-to-run noise the difference is
//! judged against. Then bytes per minute of a `sort` and a `crowd`
//! recording, and `upm replay`'s speed as a multiple of real time.

use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use anyhow::Context;
use serde_json::{Value, json};
use tungstenite::client::IntoClientRequest;

use upm_commands::launcher::{CameraChoice, RECORDING, RunPlan, run_plan};
use upm_commands::scenario::{Scenario, resolve};

/// One real run of `scenario` into `out`; its metrics.json.
fn one_run(
    scenario: &str,
    seconds: f64,
    record: bool,
    monitor: Option<u16>,
    out: &std::path::Path,
) -> anyhow::Result<Value> {
    let path = resolve(scenario);
    let sc = Scenario::load(&path)?;
    let prefix = format!("upm_bench_record_{}_", std::process::id());
    let config = sc.config(sc.seed, &prefix)?;
    upm_commands::config::validate(&config, &path.display().to_string())?;
    let plan = RunPlan {
        scenario: sc.name.clone(),
        seed: sc.seed,
        duration_s: seconds,
        config: config.clone(),
        planner_cmd: None,
        planner_ends_run: false,
        vision_cmd: None,
        stress: false,
        camera: CameraChoice::Truth,
        record,
        monitor,
        line: None,
        hmi: None,
    };
    // On a thread of its own: the launcher moves its thread off the motor's
    // CPU, and the next run checks its CPUs against this process's.
    let out = out.to_path_buf();
    let r = std::thread::scope(|s| {
        s.spawn(|| run_plan(&plan, &out, false, &|t| sc.evaluate(&config, t)).map(|o| o.metrics))
            .join()
            .map_err(|_| anyhow::anyhow!("the run panicked"))
    });
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    r?
}

/// The topics docs/foxglove-layout.json shows.
const LAYOUT_TOPICS: [&str; 4] = ["upm/scene", "upm/latency", "upm/schedule/json", "upm/telemetry/json"];

/// A Foxglove WebSocket client subscribed to `topics` (None: every
/// channel) until stopped: counts the messages it received.
fn watch(
    port: u16,
    topics: Option<&'static [&'static str]>,
    stop: Arc<AtomicBool>,
    received: Arc<AtomicU64>,
) -> anyhow::Result<()> {
    let url = format!("ws://127.0.0.1:{port}");
    let stream = loop {
        match TcpStream::connect(("127.0.0.1", port)) {
            Ok(s) => break s,
            Err(_) if !stop.load(Ordering::Relaxed) => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => return Err(e).context("connecting to the monitor"),
        }
    };
    stream.set_read_timeout(Some(Duration::from_millis(200)))?;
    let mut req = url.as_str().into_client_request()?;
    req.headers_mut().insert("Sec-WebSocket-Protocol", "foxglove.sdk.v1".parse()?);
    let (mut ws, _) = tungstenite::client(req, stream).map_err(|e| anyhow::anyhow!("handshake: {e}"))?;
    let mut next_id = 1;
    while !stop.load(Ordering::Relaxed) {
        match ws.read() {
            Ok(tungstenite::Message::Text(t)) => {
                let v: Value = serde_json::from_str(t.as_str()).unwrap_or(Value::Null);
                if v["op"] == "advertise" {
                    let subs: Vec<Value> = v["channels"]
                        .as_array()
                        .into_iter()
                        .flatten()
                        .filter(|c| topics.is_none_or(|t| t.iter().any(|t| c["topic"] == *t)))
                        .map(|c| {
                            next_id += 1;
                            json!({"id": next_id, "channelId": c["id"]})
                        })
                        .collect();
                    let msg = json!({"op": "subscribe", "subscriptions": subs}).to_string();
                    ws.send(tungstenite::Message::text(msg))?;
                }
            }
            Ok(tungstenite::Message::Binary(_)) => {
                received.fetch_add(1, Ordering::Relaxed);
            }
            Ok(_) => {}
            Err(tungstenite::Error::Io(e))
                if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {}
            // The run ended and the recorder closed the server.
            Err(tungstenite::Error::ConnectionClosed | tungstenite::Error::AlreadyClosed) => break,
            Err(e) => return Err(e).context("monitor connection"),
        }
    }
    Ok(())
}

fn p99(m: &Value, which: &str) -> f64 {
    m["latency_us"][which]["p99"].as_f64().unwrap_or(f64::NAN)
}

fn median(mut v: Vec<f64>) -> f64 {
    upm_stats::median(&mut v).unwrap_or(f64::NAN)
}

/// `rounds` pairs of `seconds`-long sort runs, then the sizes and the replay.
pub fn run(seconds: f64, rounds: usize) -> anyhow::Result<Value> {
    let base = std::env::temp_dir().join(format!("upm_bench_record_{}", std::process::id()));
    let port = std::net::TcpListener::bind("127.0.0.1:0")?.local_addr()?.port();
    let (mut without, mut recorded, mut with, mut with_all) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut monitored = [0, 0];
    let mut bytes_per_min_sort = Vec::new();
    // A run with the recorder and the monitor, watched by a client of `topics`.
    let watched =
        |topics: Option<&'static [&'static str]>, out: std::path::PathBuf| -> anyhow::Result<(Value, u64)> {
            let (stop, received) = (Arc::new(AtomicBool::new(false)), Arc::new(AtomicU64::new(0)));
            let client = {
                let (s, r) = (stop.clone(), received.clone());
                std::thread::spawn(move || watch(port, topics, s, r))
            };
            let m = one_run("sort", seconds, true, Some(port), &out);
            stop.store(true, Ordering::Relaxed);
            client.join().map_err(|_| anyhow::anyhow!("monitor client panicked"))??;
            Ok((m?, received.load(Ordering::Relaxed)))
        };
    for round in 0..rounds.max(1) {
        without.push(one_run("sort", seconds, false, None, &base.join(format!("off{round}")))?);
        recorded.push(one_run("sort", seconds, true, None, &base.join(format!("rec{round}")))?);
        let (m, n) = watched(Some(&LAYOUT_TOPICS), base.join(format!("on{round}")))?;
        monitored[0] += n;
        bytes_per_min_sort.push(m["recording"]["bytes"].as_f64().unwrap_or(f64::NAN) / (seconds / 60.0));
        with.push(m);
        let (m, n) = watched(None, base.join(format!("all{round}")))?;
        monitored[1] += n;
        with_all.push(m);
    }
    let crowd = one_run("crowd", seconds, true, None, &base.join("crowd"))?;
    let sort_file = base.join(format!("on{}", rounds.max(1) - 1)).join(RECORDING);
    let replay = upm_commands::replay::replay(&sort_file)?;
    let figures = |runs: &[Value], which: &str| runs.iter().map(|m| p99(m, which)).collect::<Vec<f64>>();
    let summary = |which: &str| {
        let (a, r, b, c) = (
            figures(&without, which),
            figures(&recorded, which),
            figures(&with, which),
            figures(&with_all, which),
        );
        let spread = a.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - a.iter().copied().fold(f64::INFINITY, f64::min);
        json!({"without_p99_us": a, "recorder_p99_us": r, "with_p99_us": b, "all_channels_p99_us": c,
               "median_without_us": median(a.clone()), "median_recorder_us": median(r.clone()),
               "median_with_us": median(b.clone()), "median_all_channels_us": median(c.clone()),
               "noise_us": spread,
               "difference_recorder_us": median(r) - median(a.clone()),
               "difference_all_channels_us": median(c) - median(a.clone()),
               "difference_us": median(b) - median(a)})
    };
    let v = json!({
        "seconds_per_run": seconds,
        "rounds": rounds,
        "motor_wakeup": summary("motor_wakeup"),
        "solver": summary("solver"),
        "overruns_without": without.iter().map(|m| m["core"]["overruns"].clone()).collect::<Vec<_>>(),
        "overruns_recorder": recorded.iter().map(|m| m["core"]["overruns"].clone()).collect::<Vec<_>>(),
        "overruns_with": with.iter().map(|m| m["core"]["overruns"].clone()).collect::<Vec<_>>(),
        "overruns_all_channels": with_all.iter().map(|m| m["core"]["overruns"].clone()).collect::<Vec<_>>(),
        "monitor_messages_received": monitored[0],
        "monitor_messages_received_all_channels": monitored[1],
        "lost_by_recorder": recorded.iter().chain(&with).map(|m| m["recording"]["lost"].clone()).collect::<Vec<_>>(),
        "bytes_per_minute_sort": median(bytes_per_min_sort),
        "bytes_per_minute_crowd": crowd["recording"]["bytes"].as_f64().unwrap_or(f64::NAN) / (seconds / 60.0),
        "replay": replay.to_json(),
        "host": crate::host_facts::read_all(),
    });
    let _ = std::fs::remove_dir_all(&base);
    Ok(v)
}

pub fn to_text(v: &Value) -> String {
    let row = |name: &str| {
        let s = &v[name];
        format!(
            "{name:<13} p99 without {:>6.1} µs  recorder {:>6.1}  +monitor (layout) {:>6.1} (difference {:>+5.1})  +monitor (all channels) {:>6.1} µs  (noise: spread of the runs without {:.1} µs)\n",
            s["median_without_us"].as_f64().unwrap_or(f64::NAN),
            s["median_recorder_us"].as_f64().unwrap_or(f64::NAN),
            s["median_with_us"].as_f64().unwrap_or(f64::NAN),
            s["difference_us"].as_f64().unwrap_or(f64::NAN),
            s["median_all_channels_us"].as_f64().unwrap_or(f64::NAN),
            s["noise_us"].as_f64().unwrap_or(f64::NAN)
        )
    };
    format!(
        "{}{}live view: {} messages to the layout's client, {} to the all-channels one; recorder lost {}\n\
         recording: sort {:.2} MB/min, crowd {:.2} MB/min\n\
         replay of sort: {} ({:.0}× real time)\n{}",
        row("motor_wakeup"),
        row("solver"),
        v["monitor_messages_received"],
        v["monitor_messages_received_all_channels"],
        v["lost_by_recorder"],
        v["bytes_per_minute_sort"].as_f64().unwrap_or(f64::NAN) / 1e6,
        v["bytes_per_minute_crowd"].as_f64().unwrap_or(f64::NAN) / 1e6,
        if v["replay"]["identical"] == true {
            "identical".to_owned()
        } else {
            format!("DIVERGED: {}", v["replay"]["divergence"])
        },
        v["replay"]["speed_x_real_time"].as_f64().unwrap_or(f64::NAN),
        crate::host_facts::to_text(&v["host"])
    )
}
