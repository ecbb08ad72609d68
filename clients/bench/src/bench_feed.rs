//! `upm bench feed`: a feed cell's throughput and presentation, lock-step
//! (the real core, simulator with its infeed and robot, vision's test
//! double and planner on a hand-stepped clock), UPM's `present` planner
//! beside the flexible feeders' shake-and-pick on the same seeds, recipe
//! and simulator in the same run. Shake-and-pick: the plate is shaken at
//! random (every part pushed a random way, redrawn every half second) and
//! the robot takes any part lying still and isolated in the pick zone, at
//! whatever angle, in the same `pick_s`.

use std::path::PathBuf;

use ipc_types::{ForceEntry, ForceRequest, PartStates};
use serde_json::{Value, json};
use upm_commands::feed_metrics::FeedOutcome;
use upm_commands::scenario::{Scenario, resolve};
use upm_planner::Planner;
use upm_stats::percentile;

/// What to run.
#[derive(Debug, Clone)]
pub struct FeedBench {
    /// The scenario (a feed cell's: its planner is `present`).
    pub scenario: String,
    /// Run the shake-and-pick baseline too.
    pub baseline: bool,
    /// The recipe instead of the scenario's.
    pub recipe: Option<PathBuf>,
    pub seeds: u64,
    pub first_seed: u64,
    pub minutes: f64,
}

/// The feeders' shake-and-pick as a planner: in each cycle the plate
/// shakes for [`SHAKE_S`] (every part pushed toward the pick zone and a
/// random way, redrawn every [`SHAKE_PERIOD_S`]; in the zone, only the
/// random way, to spread them), then rests for [`REST_S`] (zero force)
/// while the robot picks what lies still and isolated.
struct Shake {
    seed: u64,
    /// μ·m·g (N).
    mu_m_g: f64,
    /// The pick zone's centre and half-size (m).
    zone: ([f64; 2], [f64; 2]),
}

const SHAKE_S: f64 = 1.0;
const REST_S: f64 = 2.0;
const SHAKE_PERIOD_S: f64 = 0.25;
const FEED_FRACTION: f64 = 0.2;
const SPREAD_FRACTION: f64 = 0.3;

impl Shake {
    fn new(seed: u64, mu_m_g: f64, recipe: &upm_recipe::Recipe) -> Self {
        let (lo, hi) = recipe.pick_box();
        let m = drivers::feed::ZONE_MARGIN_M;
        let zone = (
            [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])],
            [0.5 * (hi[0] - lo[0]) + m, 0.5 * (hi[1] - lo[1]) + m],
        );
        Self { seed, mu_m_g, zone }
    }
}

impl Planner for Shake {
    fn name(&self) -> &'static str {
        "shake"
    }

    fn plan(&mut self, parts: &PartStates, t: f64, out: &mut ForceRequest) -> bool {
        out.clear();
        let shaking = t.rem_euclid(SHAKE_S + REST_S) < SHAKE_S;
        let slot = (t / SHAKE_PERIOD_S) as u64;
        let ([cx, cy], [hx, hy]) = self.zone;
        for p in parts.parts() {
            let mut f = [0.0; 2];
            if shaking {
                let mut rng = drivers::rng::SplitMix64::new(self.seed ^ (u64::from(p.id) << 32) ^ slot);
                let a = rng.uniform() * core::f64::consts::TAU;
                f = [SPREAD_FRACTION * self.mu_m_g * a.cos(), SPREAD_FRACTION * self.mu_m_g * a.sin()];
                let (dx, dy) = (cx - p.x, cy - p.y);
                if dx.abs() > hx || dy.abs() > hy {
                    let d = dx.hypot(dy).max(1e-9);
                    f[0] += FEED_FRACTION * self.mu_m_g * dx / d;
                    f[1] += FEED_FRACTION * self.mu_m_g * dy / d;
                }
            }
            let _ = out.push(ForceEntry::force(p.id, f));
        }
        !out.is_empty()
    }
}

/// One seed, one way: the cell's outcome.
fn one_seed(sc: &Scenario, b: &FeedBench, seed: u64, baseline: bool) -> anyhow::Result<FeedOutcome> {
    let mut config = sc.config(seed, "unused_")?;
    let seconds = b.minutes * 60.0;
    let r = if baseline {
        config.feed.robot = drivers::feed::RobotMode::AnyInZone;
        let recipe = config
            .feed_recipe("feed")?
            .ok_or_else(|| anyhow::anyhow!("the feed scenario names no recipe"))?;
        let mut shake = Shake::new(seed, config.plate.mu_m_g, &recipe);
        upm_commands::closed_loop::run(&config, &mut shake, seconds)?
    } else {
        let mut planner = config.planner.build().map_err(anyhow::Error::msg)?;
        upm_commands::closed_loop::run(&config, planner.as_mut(), seconds)?
    };
    let out = r.feed.ok_or_else(|| anyhow::anyhow!("the feed scenario ran no feed cell"))?;
    if r.hold_events > 0 || r.rejected_requests > 0 {
        eprintln!("seed {seed}: {} holds, {} rejected requests", r.hold_events, r.rejected_requests);
    }
    Ok(out)
}

/// Every seed one way, two at a time, summarised.
fn run_way(sc: &Scenario, b: &FeedBench, baseline: bool) -> anyhow::Result<Value> {
    let seeds: Vec<u64> = (0..b.seeds).map(|i| b.first_seed.wrapping_add(i)).collect();
    let runs = crate::two_at_a_time::two_at_a_time(&seeds, |seed| one_seed(sc, b, seed, baseline))?;
    let mut rates: Vec<f64> = runs.iter().filter_map(FeedOutcome::parts_per_minute).collect();
    rates.sort_by(f64::total_cmp);
    let pooled = FeedOutcome {
        picks: runs.iter().flat_map(|r| r.picks.iter().copied()).collect(),
        ..runs.first().cloned().ok_or_else(|| anyhow::anyhow!("no seed ran"))?
    };
    let (pose_mm, angle_deg) = pooled.error_p99();
    let per_seed: Vec<Value> =
        seeds.iter().zip(&runs).map(|(seed, r)| json!({ "seed": seed, "feed": r.to_json() })).collect();
    Ok(json!({
        "parts_per_minute_median": percentile(&rates, 0.5),
        "pose_error_p99_mm": pose_mm,
        "angle_error_p99_deg": angle_deg,
        "lost": runs.iter().map(|r| r.last.lost).sum::<u64>(),
        "runs": per_seed,
    }))
}

/// Both ways on the same seeds and recipe.
pub fn run(b: &FeedBench) -> anyhow::Result<Value> {
    if b.seeds == 0 {
        anyhow::bail!("--seeds must be at least 1");
    }
    if !(b.minutes.is_finite() && b.minutes > 1.0) {
        anyhow::bail!("--minutes must be more than 1 (the rate counts picks after the first minute)");
    }
    let mut sc = Scenario::load(&resolve(&b.scenario))?;
    if let Some(r) = &b.recipe {
        sc.use_recipe(r)?;
    }
    let upm = run_way(&sc, b, false)?;
    let baseline = if b.baseline { run_way(&sc, b, true)? } else { Value::Null };
    let ratio = match (upm["parts_per_minute_median"].as_f64(), baseline["parts_per_minute_median"].as_f64())
    {
        (Some(u), Some(f)) if f > 0.0 => Some(u / f),
        _ => None,
    };
    Ok(json!({
        "scenario": b.scenario,
        "recipe": b.recipe.as_ref().map_or_else(|| sc.rig.feed.recipe.clone(), |r| r.display().to_string()),
        "seeds": b.seeds,
        "first_seed": b.first_seed,
        "minutes": b.minutes,
        "upm": upm,
        "baseline": baseline,
        "ratio": ratio,
    }))
}

pub fn to_text(v: &Value) -> String {
    let line = |name: &str, w: &Value| {
        format!(
            "{name}: {} parts/min (median), pose p99 {} mm, angle p99 {}°, lost {}\n",
            w["parts_per_minute_median"], w["pose_error_p99_mm"], w["angle_error_p99_deg"], w["lost"]
        )
    };
    format!("{}{}ratio {}\n", line("upm", &v["upm"]), line("baseline", &v["baseline"]), v["ratio"])
}
