//! Load: the closed loop under CPU stress on every CPU but the motor's
//! (stress-ng if installed, else the built-in burner). The loop must keep
//! working: no hold, no RT allocation, a clean exit, and latency histograms
//! that are whole and well formed. How much the latency moves is measured
//! in BENCHMARKS.md (`upm run … --stress`, `upm bench latency --stress`),
//! never asserted here.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};

/// Percentile rows of an .hgrm file: (value µs, percentile).
fn hgrm_rows(path: &Path) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(path).expect("hgrm");
    text.lines()
        .filter_map(|l| {
            let mut it = l.split_whitespace();
            Some((it.next()?.parse().ok()?, it.next()?.parse().ok()?))
        })
        .collect()
}

fn total_count(path: &Path) -> u64 {
    let text = std::fs::read_to_string(path).expect("hgrm");
    let line = text.lines().find(|l| l.contains("Total count")).expect("Total count line");
    line.rsplit('=').next().and_then(|v| v.trim().trim_end_matches(']').trim().parse().ok()).expect("count")
}

#[test]
fn the_closed_loop_runs_under_cpu_stress_without_holds_or_allocations() {
    let prefix = common::unique_prefix("load");
    let out = std::env::temp_dir().join(format!("upm_run_stress_{}", std::process::id()));
    let o = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["run", "spin", "--duration", "5", "--stress", "--quiet", "--prefix", &prefix, "--out"])
        .arg(&out)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .expect("upm run");
    common::remove_prefix(&prefix);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).expect("metrics"))
            .expect("json");
    eprintln!("stress: {}, motor wake-up µs: {}", m["stress"], m["latency_us"]["motor_wakeup"]);
    assert!(m["stress"].as_str().is_some_and(|s| !s.is_empty()), "no load ran: {m}");
    let core = &m["core"];
    assert_eq!(core["exit_ok"], true, "{m}");
    assert_eq!(core["hold_events"], 0, "{m}");
    assert_eq!(core["rt_thread_allocations"], 0, "{m}");
    assert!(m["sim_seconds"].as_f64() >= Some(4.5), "{m}");

    // Telemetry's histogram saw (almost) every tick: the last telemetry is a
    // mid-run sample, so a few ticks may be counted before their latency
    // sample reaches the io thread. Its percentiles are ordered.
    let ticks = core["ticks"].as_u64().expect("ticks");
    let w = &m["latency_us"]["motor_wakeup"];
    let samples = w["samples"].as_u64().expect("samples");
    assert!(samples <= ticks && ticks - samples <= ticks / 100, "{samples} samples of {ticks} ticks: {m}");
    let p: Vec<f64> = ["p50", "p99", "p999", "max"].iter().map(|k| w[k].as_f64().expect("number")).collect();
    assert!(p.windows(2).all(|x| x[0] <= x[1]) && p[0] > 0.0, "{p:?}");

    // The written histograms: at least every tick telemetry saw, monotone.
    for name in ["motor_wakeup", "motor_tick", "solver", "frame_to_schedule"] {
        let path = out.join(format!("latency/{name}.hgrm"));
        let rows = hgrm_rows(&path);
        assert!(rows.len() > 2, "{name}.hgrm has no percentile rows");
        assert!(rows.windows(2).all(|r| r[0].0 <= r[1].0 && r[0].1 <= r[1].1), "{name}.hgrm not monotone");
        assert!(rows.iter().all(|r| r.0.is_finite() && r.0 >= 0.0 && (0.0..=1.0).contains(&r.1)));
        if name.starts_with("motor") {
            assert!(total_count(&path) >= ticks, "{name}.hgrm counts fewer than {ticks} ticks");
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}
