//! `upm bench latency`: the core's motor-thread wake-up latency against
//! cyclictest (rt-tests) at the same interval, priority and CPU, in the same
//! run, alternating A B A B so machine drift hits both.

use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use anyhow::{Context, bail};
use drivers::{SimConfig, Simulator};
use hdrhistogram::Histogram;
use rt_core::{CoreParams, RunOptions, run_core};
use serde_json::{Value, json};

/// Percentiles in µs.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Summary {
    pub samples: u64,
    pub p50: f64,
    pub p99: f64,
    pub p999: f64,
    pub max: f64,
}

/// p50/p99/p99.9/max of an ns histogram, in µs.
pub fn summary_ns(h: &Histogram<u64>) -> Summary {
    let us = |ns: u64| ns as f64 / 1e3;
    Summary {
        samples: h.len(),
        p50: us(h.value_at_quantile(0.5)),
        p99: us(h.value_at_quantile(0.99)),
        p999: us(h.value_at_quantile(0.999)),
        max: us(h.max()),
    }
}

pub(crate) fn new_histogram() -> anyhow::Result<Histogram<u64>> {
    Histogram::new_with_bounds(1, 100_000_000_000, 3).context("histogram")
}

/// What one run of the real core measured.
struct UpmRun {
    wakeup: Histogram<u64>,
    tick: Histogram<u64>,
    pm_qos_held: bool,
    overruns: u64,
    ticks: u64,
}

/// One run of the real core (motor + solver + io threads, simulator driver)
/// fed with the §3.1 inputs.
fn run_upm(params: &CoreParams, seconds: f64, round: usize) -> anyhow::Result<UpmRun> {
    let prefix = format!("upm_bench_lat_{}_{round}_", std::process::id());
    let stop = Arc::new(AtomicBool::new(false));
    let feeder = {
        let (p, s) = (prefix.clone(), stop.clone());
        std::thread::spawn(move || crate::feeder::feed(&p, Duration::from_millis(10), &s))
    };
    let sim = Simulator::new(SimConfig::default(), &[]).map_err(|e| anyhow::anyhow!("{e}"))?;
    let options = RunOptions {
        prefix: prefix.clone(),
        duration: Some(Duration::from_secs_f64(seconds)),
        ..RunOptions::default()
    };
    let report = run_core(params, sim, &options).map_err(|e| anyhow::anyhow!("{e}"));
    stop.store(true, Ordering::Relaxed);
    let _ = feeder.join();
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    let report = report?;
    if !report.realtime.motor.fifo {
        eprintln!("upm bench latency: WARNING: the motor thread is not SCHED_FIFO; run as root");
    }
    let c = &report.telemetry.counters;
    Ok(UpmRun {
        pm_qos_held: report.realtime.pm_qos_held,
        overruns: c.overruns,
        ticks: c.ticks,
        wakeup: report.histograms.motor_wakeup,
        tick: report.histograms.motor_tick,
    })
}

/// One cyclictest run with the same interval/priority/CPU; its per-µs
/// histogram goes into an ns histogram (bucket value × 1000).
fn run_cyclictest(
    interval_us: u64,
    priority: u8,
    cpu: Option<usize>,
    loops: u64,
) -> anyhow::Result<Histogram<u64>> {
    let mut cmd = Command::new("cyclictest");
    cmd.args(["-m", "-q", "-t1", "-h", "20000"])
        .arg(format!("-p{priority}"))
        .arg(format!("-i{interval_us}"))
        .arg(format!("-l{loops}"));
    if let Some(c) = cpu {
        cmd.arg(format!("-a{c}"));
    }
    let out = cmd.output().context("running cyclictest")?;
    if !out.status.success() {
        bail!("cyclictest failed: {}", String::from_utf8_lossy(&out.stderr).trim());
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let mut h = new_histogram()?;
    let mut max_us = 0u64;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("# Max Latencies:") {
            max_us = rest.trim().parse().unwrap_or(0);
        }
        let mut it = line.split_whitespace();
        if let (Some(a), Some(b), None) = (it.next(), it.next(), it.next())
            && let (Ok(us), Ok(n)) = (a.parse::<u64>(), b.parse::<u64>())
            && n > 0
        {
            h.saturating_record_n(us.max(1) * 1000, n);
        }
    }
    // Overflows (> 20 ms) are not in the buckets; keep the max honest.
    if max_us * 1000 > h.max() {
        h.saturating_record(max_us * 1000);
    }
    Ok(h)
}

/// Percentile curves (x: 1/(1−q), y: µs), both log-scaled, as an SVG.
pub fn plot(path: &std::path::Path, curves: &[(&str, &Histogram<u64>)]) -> anyhow::Result<()> {
    use plotters::prelude::*;
    let e = |x: &dyn std::fmt::Display| anyhow::anyhow!("{x}");
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let ymax = curves.iter().map(|(_, h)| h.max() as f64 / 1e3).fold(10.0, f64::max) * 1.5;
    let mut chart = ChartBuilder::on(&root)
        .caption("motor wake-up latency: upm vs cyclictest (same run)", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((1f64..1e6).log_scale(), (0.5f64..ymax).log_scale())
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc("1 / (1 − percentile)   (10 = p90, 100 = p99, 1000 = p99.9)")
        .y_desc("latency (µs)")
        .draw()
        .map_err(|x| e(&x))?;
    for (i, (name, h)) in curves.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        let pts: Vec<(f64, f64)> = h
            .iter_quantiles(5)
            .filter(|v| v.quantile_iterated_to() < 1.0)
            .map(|v| (1.0 / (1.0 - v.quantile_iterated_to()), (v.value_iterated_to() as f64 / 1e3).max(0.5)))
            .collect();
        chart
            .draw_series(LineSeries::new(pts, color.stroke_width(2)))
            .map_err(|x| e(&x))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
    }
    chart.configure_series_labels().border_style(BLACK).draw().map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))?;
    Ok(())
}

/// Run `rounds` × (upm, cyclictest), each `seconds` long.
pub fn run(seconds: f64, rounds: usize) -> anyhow::Result<Value> {
    run_with_plot(seconds, rounds, None, false)
}

/// What [`ab_rounds`] measured.
struct AbRounds {
    upm: Histogram<u64>,
    upm_tick: Histogram<u64>,
    cyclictest: Histogram<u64>,
    per_round: Vec<Value>,
    /// The core held its PM QoS request in every round.
    upm_pm_qos: bool,
    upm_overruns: u64,
    upm_ticks: u64,
}

/// Merged histograms of `rounds` A/B pairs, and each round's summaries.
fn ab_rounds(params: &CoreParams, seconds: f64, rounds: usize) -> anyhow::Result<AbRounds> {
    let interval_us = params.tick_ns() / 1000;
    let loops = (seconds * 1e6 / interval_us as f64) as u64;
    let (mut upm, mut upm_tick, mut ct) = (new_histogram()?, new_histogram()?, new_histogram()?);
    let mut per_round = Vec::new();
    let (mut held, mut overruns, mut ticks) = (true, 0, 0);
    for round in 0..rounds {
        let a = run_upm(params, seconds, round)?;
        held &= a.pm_qos_held;
        overruns += a.overruns;
        ticks += a.ticks;
        let b = run_cyclictest(interval_us, params.rt.motor_priority, params.rt.motor_cpu, loops)?;
        per_round.push(json!({
            "upm": summary_ns(&a.wakeup),
            "cyclictest": summary_ns(&b),
            "upm_overruns": a.overruns,
            "upm_ticks": a.ticks,
        }));
        upm.add(&a.wakeup).context("merging")?;
        upm_tick.add(&a.tick).context("merging")?;
        ct.add(&b).context("merging")?;
    }
    Ok(AbRounds {
        upm,
        upm_tick,
        cyclictest: ct,
        per_round,
        upm_pm_qos: held,
        upm_overruns: overruns,
        upm_ticks: ticks,
    })
}

/// Fraction of the samples of `h` above `ns`.
fn fraction_above(h: &Histogram<u64>, ns: u64) -> f64 {
    if h.is_empty() { 0.0 } else { h.count_between(ns.saturating_add(1), u64::MAX) as f64 / h.len() as f64 }
}

/// The host's share of overruns: a tick overruns when its wake-up lateness
/// plus its own work passes the period. The budget is the period minus the
/// tick's median work; the fraction of cyclictest's wake-ups past it is
/// what this host alone would make a motor with that work overrun.
fn overrun_budget(ab: &AbRounds, period_ns: u64) -> Value {
    let work_ns = ab.upm_tick.value_at_quantile(0.5);
    let budget_ns = period_ns.saturating_sub(work_ns);
    json!({
        "period_us": period_ns as f64 / 1e3,
        "tick_work_p50_us": work_ns as f64 / 1e3,
        "tick_work": summary_ns(&ab.upm_tick),
        "budget_us": budget_ns as f64 / 1e3,
        "upm_wakeups_past_budget": fraction_above(&ab.upm, budget_ns),
        "cyclictest_wakeups_past_budget": fraction_above(&ab.cyclictest, budget_ns),
        "upm_overruns": ab.upm_overruns,
        "upm_ticks": ab.upm_ticks,
        "upm_overrun_fraction": if ab.upm_ticks > 0 { ab.upm_overruns as f64 / ab.upm_ticks as f64 } else { 0.0 },
    })
}

/// Summaries and ratios of one A/B comparison.
fn comparison(upm: &Histogram<u64>, ct: &Histogram<u64>, per_round: Vec<Value>) -> Value {
    let (u, c) = (summary_ns(upm), summary_ns(ct));
    let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
    json!({
        "upm": u,
        "cyclictest": c,
        "ratio_p50": ratio(u.p50, c.p50),
        "ratio_p99": ratio(u.p99, c.p99),
        "ratio_p999": ratio(u.p999, c.p999),
        "ratio_max": ratio(u.max, c.max),
        "per_round": per_round,
    })
}

/// [`run`], also drawing the distributions to `plot_path`. With `stress`,
/// the same A/B rounds run again under CPU load on every CPU but the
/// motor's (stress-ng, else a built-in burner), reported as `stressed`.
pub fn run_with_plot(
    seconds: f64,
    rounds: usize,
    plot_path: Option<&std::path::Path>,
    stress: bool,
) -> anyhow::Result<Value> {
    if Command::new("cyclictest").arg("--help").output().is_err() {
        bail!(
            "cyclictest not found: install Debian's rt-tests (`apt-get install -y rt-tests`); \
             the latency bench compares against it in the same run"
        );
    }
    if !(seconds.is_finite() && seconds > 0.0) || rounds == 0 {
        bail!("--seconds must be positive and --rounds at least 1");
    }
    let params = CoreParams::default();
    let ab = ab_rounds(&params, seconds, rounds)?;
    let upm_qos = ab.upm_pm_qos;
    let mut v = comparison(&ab.upm, &ab.cyclictest, ab.per_round.clone());
    v["overrun_budget"] = overrun_budget(&ab, params.tick_ns());
    let mut curves = vec![("upm motor loop".to_owned(), ab.upm), ("cyclictest".to_owned(), ab.cyclictest)];
    if stress {
        let load =
            upm_commands::cpu_load::CpuLoad::start(&upm_commands::cpu_load::other_cpus(params.rt.motor_cpu))?;
        let s = ab_rounds(&params, seconds, rounds)?;
        let mut stressed = comparison(&s.upm, &s.cyclictest, s.per_round.clone());
        stressed["overrun_budget"] = overrun_budget(&s, params.tick_ns());
        stressed["stressor"] = json!(load.description());
        drop(load);
        v["stressed"] = stressed;
        curves.push(("upm, CPU stress".to_owned(), s.upm));
        curves.push(("cyclictest, CPU stress".to_owned(), s.cyclictest));
    }
    if let Some(p) = plot_path {
        let named: Vec<(&str, &Histogram<u64>)> = curves.iter().map(|(n, h)| (n.as_str(), h)).collect();
        plot(p, &named)?;
    }
    // cyclictest holds /dev/cpu_dma_latency at 0 unless told --laptop, if
    // it may open it: with the same rights as this process.
    let ct_qos = crate::host_facts::may_hold_pm_qos();
    v["host"] = crate::host_facts::read_all();
    v["pm_qos"] = json!({ "upm": upm_qos, "cyclictest": ct_qos, "same_policy": upm_qos == ct_qos });
    v["interval_us"] = json!(params.tick_ns() / 1000);
    v["priority"] = json!(params.rt.motor_priority);
    v["cpu"] = json!(params.rt.motor_cpu);
    v["seconds_per_run"] = json!(seconds);
    v["rounds"] = json!(rounds);
    v["note"] = json!(
        "upm: wake-up lateness of the real core's motor thread (SCHED_FIFO, absolute clock_nanosleep) with solver and io threads running; cyclictest: same interval, priority and CPU. cyclictest resolves 1 µs."
    );
    Ok(v)
}

/// The head of a table of [`summary_row`]s.
pub fn summary_header() -> String {
    format!("{:<22} {:>9} {:>9} {:>9} {:>9}", "", "p50", "p99", "p99.9", "max")
}

/// One table row of a [`Summary`] in JSON form.
pub fn summary_row(name: &str, s: &Value) -> String {
    format!(
        "{name:<22} {:>9.1} {:>9.1} {:>9.1} {:>9.1}",
        s["p50"].as_f64().unwrap_or(f64::NAN),
        s["p99"].as_f64().unwrap_or(f64::NAN),
        s["p999"].as_f64().unwrap_or(f64::NAN),
        s["max"].as_f64().unwrap_or(f64::NAN)
    )
}

/// Human-readable table.
pub fn to_text(v: &Value) -> String {
    let mut text = format!(
        "{}\nPM QoS held: upm {}, cyclictest {}\nmotor wake-up latency (µs), interval {} µs, {} rounds A/B\n{}\n{}\n{}\nratio p99 {:.2}, p99.9 {:.2}",
        crate::host_facts::to_text(&v["host"]),
        v["pm_qos"]["upm"],
        v["pm_qos"]["cyclictest"],
        v["interval_us"],
        v["rounds"],
        summary_header(),
        summary_row("upm", &v["upm"]),
        summary_row("cyclictest", &v["cyclictest"]),
        v["ratio_p99"].as_f64().unwrap_or(f64::NAN),
        v["ratio_p999"].as_f64().unwrap_or(f64::NAN),
    );
    text += &budget_text(&v["overrun_budget"]);
    let s = &v["stressed"];
    if !s.is_null() {
        text += &format!(
            "\nunder CPU stress ({}):\n{}\n{}\nratio p99 {:.2}, p99.9 {:.2}",
            s["stressor"].as_str().unwrap_or("?"),
            summary_row("upm", &s["upm"]),
            summary_row("cyclictest", &s["cyclictest"]),
            s["ratio_p99"].as_f64().unwrap_or(f64::NAN),
            s["ratio_p999"].as_f64().unwrap_or(f64::NAN),
        );
        text += &budget_text(&s["overrun_budget"]);
    }
    text
}

/// One line: how often each side woke too late for a tick to fit.
fn budget_text(b: &Value) -> String {
    let pct = |k: &str| 100.0 * b[k].as_f64().unwrap_or(f64::NAN);
    format!(
        "\n{}\nwake-ups past the overrun budget ({:.1} µs = period − tick work p50 {:.1} µs): upm {:.3} %, cyclictest {:.3} %; upm overran {:.3} % of {} ticks",
        summary_row("upm tick work", &b["tick_work"]),
        b["budget_us"].as_f64().unwrap_or(f64::NAN),
        b["tick_work_p50_us"].as_f64().unwrap_or(f64::NAN),
        pct("upm_wakeups_past_budget"),
        pct("cyclictest_wakeups_past_budget"),
        pct("upm_overrun_fraction"),
        b["upm_ticks"],
    )
}
