//! `upm bench ipc`: one-way PartStates latency from a vision publisher to
//! the core's solver stage, against a raw iceoryx2 ping-pong of the same
//! payload (round trip halved), in the same run.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use anyhow::Context;
use drivers::{SimConfig, Simulator};
use hdrhistogram::Histogram;
use iceoryx2::prelude::*;
use ipc_types::ports::open_pub_sub;
use ipc_types::rig_node::rig_node;
use ipc_types::{PartStates, monotonic_now_ns};
use rt_core::runtime::{CoreParams, RunOptions, run_core};
use serde_json::{Value, json};

use crate::bench_latency::{summary_ns as summary, summary_row};

fn node(prefix: &str) -> anyhow::Result<Node<ipc::Service>> {
    Ok(rig_node(prefix, None, SignalHandlingMode::Disabled)?)
}

/// Raw iceoryx2: ping on one service, echo on another, busy polling both
/// sides; one-way = round trip / 2.
fn raw_ping_pong(samples: usize) -> anyhow::Result<Histogram<u64>> {
    let prefix = format!("upm_bench_raw_{}_", std::process::id());
    let stop = Arc::new(AtomicBool::new(false));
    let ponger = {
        let (prefix, stop) = (prefix.clone(), stop.clone());
        std::thread::spawn(move || -> anyhow::Result<()> {
            let n = node(&prefix)?;
            let ping = open_pub_sub::<PartStates>(&n, "bench/ping")?
                .subscriber_builder()
                .create()
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            let pong = open_pub_sub::<PartStates>(&n, "bench/pong")?
                .publisher_builder()
                .create()
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            while !stop.load(Ordering::Relaxed) {
                if let Some(s) = ping.receive().map_err(|e| anyhow::anyhow!("{e:?}"))? {
                    pong.send_copy(*s.payload()).map_err(|e| anyhow::anyhow!("{e:?}"))?;
                }
            }
            Ok(())
        })
    };
    let n = node(&prefix)?;
    let ping = open_pub_sub::<PartStates>(&n, "bench/ping")?
        .publisher_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let pong = open_pub_sub::<PartStates>(&n, "bench/pong")?
        .subscriber_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    std::thread::sleep(Duration::from_millis(100));
    let mut h = Histogram::new_with_bounds(1, 100_000_000_000, 3).context("histogram")?;
    let mut msg = PartStates::new();
    let mut warm = 0;
    while (h.len() as usize) < samples {
        msg.stamp_ns = monotonic_now_ns();
        ping.send_copy(msg).map_err(|e| anyhow::anyhow!("{e:?}"))?;
        let give_up = msg.stamp_ns + 1_000_000_000;
        loop {
            if let Some(s) = pong.receive().map_err(|e| anyhow::anyhow!("{e:?}"))? {
                let one_way = (monotonic_now_ns() - s.payload().stamp_ns) / 2;
                warm += 1;
                if warm > 100 {
                    h.saturating_record(one_way.max(1));
                }
                break;
            }
            if monotonic_now_ns() > give_up {
                break;
            }
        }
    }
    stop.store(true, Ordering::Relaxed);
    let _ = ponger.join();
    crate::status::remove_prefix_segment(&prefix);
    Ok(h)
}

/// The core's own measurement: PartStates stamp → validated on the solver
/// thread, with a feeder publishing at 1 kHz.
fn upm_one_way(seconds: f64, poll_ns: u64) -> anyhow::Result<Histogram<u64>> {
    let prefix = format!("upm_bench_ipc_{}_", std::process::id());
    let stop = Arc::new(AtomicBool::new(false));
    let feeder = {
        let (p, s) = (prefix.clone(), stop.clone());
        std::thread::spawn(move || crate::feeder::feed(&p, Duration::from_millis(1), &s))
    };
    let sim = Simulator::new(SimConfig::default(), &[]).map_err(|e| anyhow::anyhow!("{e}"))?;
    let options = RunOptions {
        prefix: prefix.clone(),
        duration: Some(Duration::from_secs_f64(seconds)),
        ..RunOptions::default()
    };
    let params = CoreParams { solver_poll_ns: poll_ns, ..CoreParams::default() };
    let report = run_core(&params, sim, &options).map_err(|e| anyhow::anyhow!("{e}"));
    stop.store(true, Ordering::Relaxed);
    let _ = feeder.join();
    crate::status::remove_prefix_segment(&prefix);
    Ok(report?.histograms.ipc_vision_to_core)
}

pub fn run(seconds: f64) -> anyhow::Result<Value> {
    let raw = raw_ping_pong(10_000)?;
    let default_poll = CoreParams::default().solver_poll_ns;
    let upm = upm_one_way(seconds, default_poll)?;
    let fast = upm_one_way(seconds, 50_000)?;
    let (u, r, f) = (summary(&upm), summary(&raw), summary(&fast));
    Ok(json!({
        "payload_bytes": size_of::<PartStates>(),
        "upm": u,
        "raw_iceoryx2": r,
        "solver_poll_us": default_poll / 1000,
        "upm_poll_50us": f,
        "ratio_p99_poll_50us": f.p99 / r.p99,
        "ratio_p50": u.p50 / r.p50,
        "ratio_p99": u.p99 / r.p99,
        "note": "upm: PartStates stamp → validated by the core's solver stage (publisher → iceoryx2 → receiver thread → ring → solver poll); raw: busy-polled ping-pong of the same payload, round trip / 2.",
    }))
}

pub fn to_text(v: &Value) -> String {
    let row = summary_row;
    format!(
        "one-way PartStates latency (µs), payload {} B\n{:<16} {:>9} {:>9} {:>9} {:>9}\n{}\n{}\nratio p99 {:.1}\n{}\nratio p99 (50 µs poll) {:.1}",
        v["payload_bytes"],
        "",
        "p50",
        "p99",
        "p99.9",
        "max",
        row("upm", &v["upm"]),
        row("raw iceoryx2", &v["raw_iceoryx2"]),
        v["ratio_p99"].as_f64().unwrap_or(f64::NAN),
        row("upm, 50 µs poll", &v["upm_poll_50us"]),
        v["ratio_p99_poll_50us"].as_f64().unwrap_or(f64::NAN)
    )
}
