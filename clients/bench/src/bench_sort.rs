//! `upm bench sort`: how long a sort scenario takes to put every part on
//! its side, over many seeds, in lock-step (the real core, simulator and
//! planner on a hand-stepped clock; vision's camera model), so a figure is
//! bit-reproducible and independent of the host's load. The baseline (the
//! paper's way, `sort_paper`) runs on the same seeds in the same run.

use serde_json::{Value, json};

use upm_commands::scenario::{Scenario, resolve};

/// What to run.
#[derive(Debug, Clone)]
pub struct SortBench {
    /// A scenario whose planner is `sort` or `sort_paper` (name or path).
    pub scenario: String,
    /// The reference run on the same seeds (name or path); None: none.
    pub baseline: Option<String>,
    pub seeds: u64,
    pub first_seed: u64,
    /// Simulated seconds per seed (the scenario's `duration_s` if None).
    pub seconds: Option<f64>,
    /// The planner sees the simulator's truth, or rendered frames through
    /// vision's pipeline.
    pub camera: upm_commands::launcher::CameraChoice,
    /// What moves the plate (the scenario's `[driver]` if None).
    pub driver: Option<upm_commands::config::DriverChoice>,
    /// The plate's hidden truth (the scenario's `[sim] truth` if None).
    pub truth: Option<String>,
}

/// One seed's outcome.
fn one_seed(
    sc: &Scenario,
    seed: u64,
    seconds: f64,
    camera: upm_commands::launcher::CameraChoice,
    driver: Option<upm_commands::config::DriverChoice>,
    truth: Option<&str>,
) -> anyhow::Result<Value> {
    let mut config = sc.config(seed, "unused_")?;
    if let Some(kind) = driver {
        config.driver.kind = kind;
    }
    if let Some(t) = truth {
        config.sim.truth = upm_commands::config::truth::TruthSection::Preset(t.to_owned());
    }
    let mut planner = config.planner.build().map_err(anyhow::Error::msg)?;
    let r = upm_commands::closed_loop::run_seeing(&config, planner.as_mut(), seconds, camera)?;
    let m = sc.evaluate(&config, &r.trails);
    Ok(json!({
        "seed": seed,
        "time_to_sort_s": m["time_to_sort_s"],
        "sorted_fraction": m["sorted_fraction"],
        "collisions": m["collisions"],
        "hold_events": r.hold_events,
        "detected_merged_bad_frames": r.sight,
    }))
}

use upm_stats::percentile;

/// Run every seed of both scenarios and summarise: the scenario's figures
/// at the top level, the baseline's under `baseline` and as
/// `baseline_median_s`.
pub fn run(b: &SortBench) -> anyhow::Result<Value> {
    if b.seeds == 0 {
        anyhow::bail!("--seeds must be at least 1");
    }
    let mut v = run_one(b, &b.scenario)?;
    if let Some(baseline) = &b.baseline {
        let base = run_one(b, baseline)?;
        v["baseline_median_s"] = base["median_s"].clone();
        v["baseline"] = base;
    }
    Ok(v)
}

/// Every seed of one scenario (two at a time: the runs are independent and
/// deterministic). A seed that is not sorted in time ranks after every
/// sorted one: the maximum is then null, and so is any percentile that
/// lands on it, so an unsorted seed can never pass for a fast one.
fn run_one(b: &SortBench, scenario: &str) -> anyhow::Result<Value> {
    let sc = Scenario::load(&resolve(scenario))?;
    if !matches!(sc.planner.name(), "sort" | "sort_paper") {
        anyhow::bail!(
            "{scenario}: upm bench sort needs a scenario whose planner is sort or sort_paper, not {}",
            sc.planner.name()
        );
    }
    let seconds = b.seconds.unwrap_or(sc.duration_s);
    let seeds: Vec<u64> = (0..b.seeds).map(|i| b.first_seed.wrapping_add(i)).collect();
    let runs = crate::two_at_a_time::two_at_a_time(&seeds, |seed| {
        one_seed(&sc, seed, seconds, b.camera, b.driver, b.truth.as_deref())
    })?;
    let mut times: Vec<f64> =
        runs.iter().map(|r| r["time_to_sort_s"].as_f64().unwrap_or(f64::INFINITY)).collect();
    times.sort_by(f64::total_cmp);
    let timed = |t: Option<f64>| t.filter(|t| t.is_finite());
    let sorted = times.iter().filter(|t| t.is_finite()).count();
    let mut collisions: Vec<f64> = runs.iter().filter_map(|r| r["collisions"].as_f64()).collect();
    collisions.sort_by(f64::total_cmp);
    Ok(json!({
        "scenario": sc.name,
        "planner": sc.planner.name(),
        "camera": format!("{:?}", b.camera).to_lowercase(),
        "driver": b.driver.map_or_else(|| "scenario".to_owned(), |d| format!("{d:?}")),
        "truth": b.truth.as_deref().unwrap_or("scenario"),
        "seeds": b.seeds,
        "first_seed": b.first_seed,
        "seconds_per_seed": seconds,
        "median_s": timed(percentile(&times, 0.5)),
        "p90_s": timed(percentile(&times, 0.9)),
        "max_s": timed(times.last().copied()),
        "sorted_fraction": sorted as f64 / runs.len() as f64,
        "collisions_median": percentile(&collisions, 0.5),
        "runs": runs,
    }))
}

pub fn to_text(v: &Value) -> String {
    let mut out = summary_text(v);
    if !v["baseline"].is_null() {
        out += "baseline: ";
        out += &summary_text(&v["baseline"]);
    }
    out
}

fn summary_text(v: &Value) -> String {
    let s = |x: &Value| x.as_f64().map_or("—".into(), |t| format!("{t:.1} s"));
    let mut out = format!(
        "{} ({} planner), {} seeds from {}, {} s each, lock-step\n\
         time to sort: median {}, p90 {}, max {}; sorted {:.0} % of seeds; collisions median {}\n",
        v["scenario"].as_str().unwrap_or("?"),
        v["planner"].as_str().unwrap_or("?"),
        v["seeds"],
        v["first_seed"],
        v["seconds_per_seed"],
        s(&v["median_s"]),
        s(&v["p90_s"]),
        s(&v["max_s"]),
        100.0 * v["sorted_fraction"].as_f64().unwrap_or(0.0),
        v["collisions_median"],
    );
    for r in v["runs"].as_array().into_iter().flatten() {
        out += &format!(
            "  seed {:>4}: {:>8}, collisions {}\n",
            r["seed"],
            s(&r["time_to_sort_s"]),
            r["collisions"]
        );
    }
    out
}
