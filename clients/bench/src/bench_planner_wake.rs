//! `upm bench ipc`'s planner wake-up: vision's PartStates publish and its
//! notification of the `upm/part_states` event → a planner woken on that
//! event with the newest PartStates in hand, one way, for a Rust listener
//! and a Python one (iceoryx2's own package), beside a raw iceoryx2 event
//! ping (notify → listener woken, no payload) in the same run. Each is
//! paced like a 1 kHz camera and measured alone.

use std::io::{BufRead, BufReader, Read};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use hdrhistogram::Histogram;
use iceoryx2::prelude::*;
use ipc_types::rig_node::remove_prefix_segment;
use ipc_types::wake_event::{WakeEvent, WakeNotifier, wake_listener};
use ipc_types::{PartStates, monotonic_now_ns, service_names};
use serde_json::{Value, json};

use crate::bench_latency::{new_histogram, summary_ns as summary};
use crate::ipc_probe::node;

/// Wake-ups before recording starts (connections, caches, Python's start).
const WARM_UP: usize = 100;
const PERIOD: Duration = Duration::from_millis(1);
/// Longest a listener waits in one go (so it sees the stop flag).
const WAIT: Duration = Duration::from_millis(10);

/// The figures, as JSON keys of `upm bench ipc` (see [`crate::bench_ipc::to_text`]).
pub fn run(samples: usize) -> anyhow::Result<Value> {
    let rust = rust_listener(samples)?;
    let raw = raw_event(samples)?;
    let (python, python_note) = match find_python() {
        Ok((py, version)) => match python_listener(&py, samples) {
            Ok(h) => (Some(summary(&h)), json!({"python": py.display().to_string(), "iceoryx2": version})),
            Err(e) => (None, json!({"skipped": format!("the Python listener failed: {e:#}")})),
        },
        Err(why) => (None, json!({"skipped": why})),
    };
    let (r, w) = (summary(&rust), summary(&raw));
    Ok(json!({
        "planner_wake_rust": r,
        "planner_wake_python": python,
        "planner_wake_python_run": python_note,
        "raw_iceoryx2_event_wake": w,
        "ratio_p50_planner_wake_rust_vs_raw_event": r.p50 / w.p50,
        "ratio_p50_planner_wake_python_vs_raw_event": python.as_ref().map(|p| p.p50 / w.p50),
    }))
}

/// Vision's side: publish a stamped PartStates and notify the planners'
/// event every period, until `done` (or `limit` messages).
fn publish_until(prefix: &str, done: &dyn Fn() -> bool, limit: usize) -> anyhow::Result<()> {
    let n = node(prefix)?;
    let publisher = ipc_types::ports::publisher::<PartStates>(&n, service_names::PART_STATES)?;
    let mut wake = WakeNotifier::new(&n, WakeEvent::PartStates)?;
    let mut msg = PartStates::new();
    for seq in 1..=limit as u64 {
        if done() {
            break;
        }
        msg.seq = seq;
        msg.stamp_ns = monotonic_now_ns();
        publisher.send_copy(msg).map_err(|e| anyhow::anyhow!("publishing part states: {e:?}"))?;
        wake.notify();
        std::thread::sleep(PERIOD);
    }
    Ok(())
}

/// A Rust planner: sleeps on the event, then takes the newest PartStates.
fn rust_listener(samples: usize) -> anyhow::Result<Histogram<u64>> {
    let prefix = ipc_types::rig_node::unique_prefix("upm_bench_wake");
    let stop = Arc::new(AtomicBool::new(false));
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let listener = {
        let (prefix, stop) = (prefix.clone(), stop.clone());
        std::thread::spawn(move || -> anyhow::Result<Histogram<u64>> {
            let n = node(&prefix)?;
            let parts = ipc_types::ports::subscriber::<PartStates>(&n, service_names::PART_STATES)?;
            let woken = wake_listener(&n, WakeEvent::PartStates)?;
            let _ = ready_tx.send(());
            let mut h = new_histogram()?;
            let mut seen = 0;
            while !stop.load(Ordering::Relaxed) && (h.len() as usize) < samples {
                woken.timed_wait(|_| {}, WAIT).map_err(|e| anyhow::anyhow!("waiting: {e:?}"))?;
                let mut newest = None;
                while let Some(s) = parts.receive().map_err(|e| anyhow::anyhow!("receiving: {e:?}"))? {
                    newest = Some(s.payload().stamp_ns);
                }
                let now = monotonic_now_ns();
                if let Some(stamp) = newest {
                    seen += 1;
                    if seen > WARM_UP {
                        h.saturating_record(now.saturating_sub(stamp).max(1));
                    }
                }
            }
            Ok(h)
        })
    };
    let _ = ready_rx.recv_timeout(Duration::from_secs(10));
    let done = || listener.is_finished();
    let fed = publish_until(&prefix, &done, (samples + WARM_UP) * 2);
    stop.store(true, Ordering::Relaxed);
    let h = listener.join().map_err(|_| anyhow::anyhow!("the listener thread panicked"))?;
    remove_prefix_segment(&prefix);
    fed?;
    let h = h?;
    anyhow::ensure!(h.len() as usize >= samples, "the Rust listener got {} of {samples} wake-ups", h.len());
    Ok(h)
}

/// The reference: a raw iceoryx2 event (default settings, no payload):
/// stamp, notify, the listener thread woken.
fn raw_event(samples: usize) -> anyhow::Result<Histogram<u64>> {
    let prefix = ipc_types::rig_node::unique_prefix("upm_bench_rawev");
    let stop = Arc::new(AtomicBool::new(false));
    let stamp = Arc::new(AtomicU64::new(0));
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let event = |n: &Node<ipc::Service>| crate::ipc_probe::raw_event(n, "bench/event");
    let listener = {
        let (prefix, stop, stamp) = (prefix.clone(), stop.clone(), stamp.clone());
        std::thread::spawn(move || -> anyhow::Result<Histogram<u64>> {
            let n = node(&prefix)?;
            let woken = event(&n)?.listener_builder().create().map_err(|e| anyhow::anyhow!("{e:?}"))?;
            let _ = ready_tx.send(());
            let mut h = new_histogram()?;
            let mut seen = 0;
            while !stop.load(Ordering::Relaxed) && (h.len() as usize) < samples {
                let mut got = false;
                woken.timed_wait(|_| got = true, WAIT).map_err(|e| anyhow::anyhow!("{e:?}"))?;
                let now = monotonic_now_ns();
                if got {
                    seen += 1;
                    if seen > WARM_UP {
                        h.saturating_record(now.saturating_sub(stamp.load(Ordering::Acquire)).max(1));
                    }
                }
            }
            Ok(h)
        })
    };
    let _ = ready_rx.recv_timeout(Duration::from_secs(10));
    let n = node(&prefix)?;
    let notifier = event(&n)?.notifier_builder().create().map_err(|e| anyhow::anyhow!("{e:?}"))?;
    for _ in 0..(samples + WARM_UP) * 2 {
        if listener.is_finished() {
            break;
        }
        stamp.store(monotonic_now_ns(), Ordering::Release);
        notifier.notify().map_err(|e| anyhow::anyhow!("{e:?}"))?;
        std::thread::sleep(PERIOD);
    }
    stop.store(true, Ordering::Relaxed);
    let h = listener.join().map_err(|_| anyhow::anyhow!("the listener thread panicked"))?;
    drop((notifier, n));
    remove_prefix_segment(&prefix);
    let h = h?;
    anyhow::ensure!(h.len() as usize >= samples, "the raw listener got {} of {samples} wake-ups", h.len());
    Ok(h)
}

/// A Python that imports iceoryx2 0.10: `UPM_PYTHON`, else `python3`.
fn find_python() -> Result<(PathBuf, String), String> {
    let py = std::env::var_os("UPM_PYTHON").map_or_else(|| PathBuf::from("python3"), PathBuf::from);
    let probe = "import importlib.metadata as m, iceoryx2; print(m.version('iceoryx2'))";
    match Command::new(&py).args(["-c", probe]).output() {
        Ok(o) if o.status.success() => {
            let version = String::from_utf8_lossy(&o.stdout).trim().to_owned();
            if version.starts_with("0.10.") {
                Ok((py, version))
            } else {
                Err(format!("{} has iceoryx2 {version}, the rig speaks 0.10.x", py.display()))
            }
        }
        _ => Err(format!(
            "no Python listener: {} cannot import iceoryx2 (set UPM_PYTHON to a Python with \
             `pip install iceoryx2==0.10.0`)",
            py.display()
        )),
    }
}

/// The Python planner, as the shipped package (`clients/python`,
/// `upm_ipc`) does it: `wait_part_states`, then `newest_part_states`;
/// prints one latency (ns) a line.
const PYTHON_LISTENER: &str = r#"
import sys, time, upm_ipc
prefix, samples = sys.argv[1], int(sys.argv[2])
rig = upm_ipc.connect(prefix, name="upm-bench-py")
print("ready", flush=True)
got, end = 0, time.monotonic() + 60
while got < samples and time.monotonic() < end:
    woken = rig.wait_part_states(0.1)
    if woken is None:
        break
    states = rig.newest_part_states() if woken else None
    now = upm_ipc.monotonic_now_ns()
    if states is not None:
        got += 1
        print(now - states.stamp_ns, flush=True)
"#;

fn python_listener(py: &std::path::Path, samples: usize) -> anyhow::Result<Histogram<u64>> {
    let prefix = ipc_types::rig_node::unique_prefix("upm_bench_pywake");
    let total = samples + WARM_UP;
    let mut child = Command::new(py)
        .args(["-c", PYTHON_LISTENER, &prefix, &total.to_string()])
        .env("PYTHONPATH", concat!(env!("CARGO_MANIFEST_DIR"), "/../python"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()?;
    let stdout = child.stdout.take().ok_or_else(|| anyhow::anyhow!("no stdout"))?;
    let (tx, rx) = std::sync::mpsc::channel::<String>();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let started = Instant::now();
    let ready = loop {
        match rx.recv_timeout(Duration::from_millis(100)) {
            Ok(l) if l == "ready" => break true,
            Ok(_) => {}
            Err(_) if started.elapsed() > Duration::from_secs(20) || child.try_wait()?.is_some() => {
                break false;
            }
            Err(_) => {}
        }
    };
    // Vision publishes until Python has reported every wake-up (or quit).
    let latencies = std::cell::RefCell::new(Vec::with_capacity(total));
    let take = |lines: &std::sync::mpsc::Receiver<String>| {
        while let Ok(l) = lines.try_recv() {
            if let Ok(ns) = l.trim().parse::<u64>() {
                latencies.borrow_mut().push(ns);
            }
        }
    };
    let fed = if ready {
        let done = || {
            take(&rx);
            latencies.borrow().len() >= total
        };
        publish_until(&prefix, &done, total * 3)
    } else {
        Ok(())
    };
    if child.try_wait()?.is_none() && latencies.borrow().len() < total {
        let _ = child.kill();
    }
    let status = child.wait()?;
    let _ = reader.join();
    take(&rx);
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = e.read_to_string(&mut err);
    }
    remove_prefix_segment(&prefix);
    anyhow::ensure!(ready, "it never became ready: {}", err.trim());
    fed?;
    anyhow::ensure!(status.success(), "exit {status}: {}", err.trim());
    let mut h = new_histogram()?;
    for &ns in latencies.borrow().iter().skip(WARM_UP) {
        h.saturating_record(ns.max(1));
    }
    anyhow::ensure!(h.len() as usize >= samples, "the Python listener got {} of {samples} wake-ups", h.len());
    Ok(h)
}
