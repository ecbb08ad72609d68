//! `upm bench fidelity`'s closed-loop half: the scenarios whose parts have
//! outlines, run lock-step with the core on the per-shape model with and
//! without its part-dynamics correction (`[motion.part_dynamics]`), and on
//! the paper's point model (`[motion] part_shapes`), same seeds, same
//! camera.
//! What counts is what a planner sees: whether the turning part settles
//! and how long it takes, how far it strays from its straight path, and
//! how still the parts asked to stay are.

use serde_json::{Value, json};

use upm_commands::scenario::{Scenario, resolve};
use upm_motion::LinearizeAbout;
use upm_planner::PlannerConfig;

/// The scenarios measured: turn in place (disc, square), turn while
/// crossing the plate, move one part past others.
pub const SCENARIOS: [&str; 4] = ["spin", "spin_square", "orient", "local"];

/// One configuration of the core (and the damping its `spin` planner
/// needs with it).
#[derive(Debug, Clone, Copy)]
pub struct Model {
    pub name: &'static str,
    pub part_shapes: bool,
    /// Part-dynamics correction steps (0: off) and the state it starts from.
    pub dynamics_steps: u32,
    pub about: LinearizeAbout,
    /// `spin`'s `damping`: a core that corrects for the part's own spin no
    /// longer damps it (0.3 settles `spin` fastest of 0.05, 0.15, 0.3 on
    /// seed 1).
    pub spin_damping: f64,
}

/// The models compared: the correction about the reported state and from
/// rest, the per-shape model alone, the paper's point model.
pub const MODELS: [Model; 4] = [
    Model {
        name: "reported",
        part_shapes: true,
        dynamics_steps: 2,
        about: LinearizeAbout::Reported,
        spin_damping: 0.3,
    },
    Model {
        name: "rest",
        part_shapes: true,
        dynamics_steps: 2,
        about: LinearizeAbout::Rest,
        spin_damping: 0.0,
    },
    Model {
        name: "shapes",
        part_shapes: true,
        dynamics_steps: 0,
        about: LinearizeAbout::Reported,
        spin_damping: 0.0,
    },
    Model {
        name: "points",
        part_shapes: false,
        dynamics_steps: 0,
        about: LinearizeAbout::Reported,
        spin_damping: 0.0,
    },
];

/// One scenario on one seed with one model: the figures kept.
fn one(sc: &Scenario, seed: u64, model: Model) -> anyhow::Result<Value> {
    let mut config = sc.config(seed, "unused_")?;
    config.motion.part_shapes = model.part_shapes;
    config.motion.part_dynamics.steps = model.dynamics_steps;
    config.motion.part_dynamics.about = model.about;
    if let PlannerConfig::Spin(p) = &mut config.planner {
        p.damping = model.spin_damping;
    }
    let mut planner = config.planner.build().map_err(anyhow::Error::msg)?;
    let r = upm_commands::closed_loop::run(&config, planner.as_mut(), sc.duration_s)?;
    let mut m = sc.evaluate(&config, &r.trails);
    let part = match &sc.planner {
        PlannerConfig::Spin(p) => p.part,
        PlannerConfig::Local(p) => p.part,
        _ => anyhow::bail!("{}: not a spin or local scenario", sc.name),
    };
    // How far the part that turns or moves strays from the straight line
    // between where it began and where it ended.
    m["path_deviation_m"] = json!(r.trails.parts.get(&part).map(|t| path_deviation(&t.points)));
    m["hold_events"] = json!(r.hold_events);
    m["rejected_requests"] = json!(r.rejected_requests);
    Ok(m)
}

fn path_deviation(points: &[[f64; 4]]) -> f64 {
    let (Some(a), Some(b)) = (points.first(), points.last()) else { return 0.0 };
    let d = [b[1] - a[1], b[2] - a[2]];
    let len = d[0].hypot(d[1]);
    points
        .iter()
        .map(|q| {
            let v = [q[1] - a[1], q[2] - a[2]];
            if len > 0.0 { (v[0] * d[1] - v[1] * d[0]).abs() / len } else { v[0].hypot(v[1]) }
        })
        .fold(0.0, f64::max)
}

/// Every scenario on `seeds`, both models.
pub fn run(seeds: &[u64]) -> anyhow::Result<Value> {
    let mut out = serde_json::Map::new();
    for name in SCENARIOS {
        let sc = Scenario::load(&resolve(name))?;
        let mut per_model = serde_json::Map::new();
        for model in MODELS {
            let runs: Vec<Value> =
                seeds.iter().map(|&s| one(&sc, s, model)).collect::<anyhow::Result<_>>()?;
            per_model.insert(model.name.into(), summarize(&runs));
        }
        out.insert(name.into(), Value::Object(per_model));
    }
    Ok(json!({ "seeds": seeds, "scenarios": out }))
}

/// Goals met, and the worst and median of each figure over the seeds.
fn summarize(runs: &[Value]) -> Value {
    let met = runs
        .iter()
        .filter(|m| m["parts"].as_array().is_some_and(|p| p.iter().all(|p| p["goal_met"] == true)))
        .count();
    let stat = |key: &str, abs: bool| {
        let mut v: Vec<f64> =
            runs.iter().filter_map(|m| m[key].as_f64()).map(|x| if abs { x.abs() } else { x }).collect();
        v.sort_by(f64::total_cmp);
        json!({ "median": upm_stats::percentile(&v, 0.5), "worst": v.last(), "of": v.len() })
    };
    json!({
        "runs": runs.len(),
        "goals_met": met,
        "holds": runs.iter().filter_map(|m| m["hold_events"].as_u64()).sum::<u64>(),
        "rejected": runs.iter().filter_map(|m| m["rejected_requests"].as_u64()).sum::<u64>(),
        "spin_settled_s": stat("spin_settled_s", false),
        "spin_angle_error_deg": stat("spin_angle_error_deg", true),
        "path_deviation_m": stat("path_deviation_m", false),
        "others_max_drift_m": stat("others_max_drift_m", false),
    })
}

/// One line per scenario and model.
pub fn to_text(v: &Value) -> String {
    let f = |x: &Value, scale: f64, unit: &str| {
        x.as_f64().map_or("—".into(), |x| format!("{:.2}{unit}", x * scale))
    };
    let mut s = format!("closed loop, lock-step, seeds {}:\n", v["seeds"]);
    if let Some(map) = v["scenarios"].as_object() {
        for (name, models) in map {
            for model in MODELS.map(|m| m.name) {
                let m = &models[model];
                s += &format!(
                    "  {name:<12} {model:<8} goals {}/{}, settled within 2° at {} (worst {}), angle error worst {}, \
                     path deviation worst {}, others' drift worst {}\n",
                    m["goals_met"],
                    m["runs"],
                    f(&m["spin_settled_s"]["median"], 1.0, " s"),
                    f(&m["spin_settled_s"]["worst"], 1.0, " s"),
                    f(&m["spin_angle_error_deg"]["worst"], 1.0, "°"),
                    f(&m["path_deviation_m"]["worst"], 1e3, " mm"),
                    f(&m["others_max_drift_m"]["worst"], 1e3, " mm"),
                );
            }
        }
    }
    s
}
