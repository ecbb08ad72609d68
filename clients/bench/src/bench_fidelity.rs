//! `upm bench fidelity`: how well a solved schedule's forces and curls
//! arrive at extended parts. Random geometries (1–10 parts, points, discs
//! and convex polygons 10–40 mm across, some asked for force and curl
//! together, 9–24 centers on and just beyond the plate), each solved with
//! the per-shape model corrected for the velocity parts pick up through
//! the cycle (`part_dynamics`), with the per-shape model alone (parts at
//! rest, `static_*`) and, as the baseline, with the paper's point model,
//! all in the same run and played on the same shaped parts in the
//! simulator (`validate::measure`). Force error is relative to the request
//! plus 0.005 μmg; curl error relative to the request. Requests the model
//! cannot meet exactly (saturated) are drawn again and counted.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use upm_paper::solve_json::{PartInput, ShapeInput, SolveInput, solve};
use upm_paper::validate::{ValidateSetup, measure};

/// Cycles each solution is played for.
const CYCLES: usize = 2;

fn random_case(rng: &mut ChaCha8Rng) -> SolveInput {
    let n = rng.random_range(9..=24usize);
    let centers = (0..n).map(|_| [rng.random_range(-1.1..1.1), rng.random_range(-0.6..0.6)]).collect();
    let count = rng.random_range(1..=10usize);
    let mut parts: Vec<PartInput> = Vec::new();
    while parts.len() < count {
        let position = [rng.random_range(-0.8..0.8), rng.random_range(-0.4..0.4)];
        if parts.iter().any(|p| (p.position[0] - position[0]).hypot(p.position[1] - position[1]) < 0.1) {
            continue;
        }
        let half = 0.5 * rng.random_range(0.010..0.040);
        let shape = match rng.random_range(0..4u32) {
            0 => ShapeInput::Point,
            1 | 2 => ShapeInput::Disc { radius: half },
            _ => {
                let sides = rng.random_range(3..=6usize);
                let turn = rng.random_range(0.0..core::f64::consts::TAU);
                let vertices = (0..sides)
                    .map(|i| {
                        let a = turn + core::f64::consts::TAU * i as f64 / sides as f64;
                        [half * a.cos(), half * a.sin()]
                    })
                    .collect();
                ShapeInput::Polygon { vertices }
            }
        };
        let f = rng.random_range(0.001..0.01);
        let a = rng.random_range(0.0..core::f64::consts::TAU);
        let curl = (shape != ShapeInput::Point && rng.random_range(0.0..1.0) < 0.4).then(|| {
            rng.random_range(0.002..0.01) * if rng.random_range(0.0..1.0) < 0.5 { -1.0 } else { 1.0 }
        });
        parts.push(PartInput {
            position,
            force: Some([f * a.cos(), f * a.sin()]),
            shape,
            curl,
            friction: None,
        });
    }
    SolveInput { mu_m_g: 0.1, centers, parts, curls: Vec::new(), k_max: Some(0.75), part_dynamics: true }
}

/// Per-part force errors and per-curl errors of one case solved from
/// `model` and played on the parts of `input`.
fn errors(input: &SolveInput, model: &SolveInput, seed: u64) -> anyhow::Result<Option<(Vec<f64>, Vec<f64>)>> {
    let out = solve(model)?;
    if out.saturated || out.residual > 1e-9 {
        return Ok(None);
    }
    let order: Vec<u16> = out.order.iter().map(|&j| j as u16).collect();
    let m = measure(input, &out.k, &order, CYCLES, seed, &ValidateSetup::default(), &[])?;
    let mu = input.mu_m_g;
    let force = input
        .parts
        .iter()
        .zip(&m.forces)
        .filter_map(|(p, s)| p.force.map(|f| upm_paper::solve_json::relative_force_error(f, *s, mu)))
        .collect();
    let asked = input.parts.iter().filter_map(|p| p.curl);
    let curl = asked.zip(&m.curls).map(|(c, s)| ((s - c) / c).abs()).collect();
    Ok(Some((force, curl)))
}

fn summary(v: &mut [f64]) -> (Option<f64>, Option<f64>) {
    v.sort_by(f64::total_cmp);
    (upm_stats::percentile(v, 0.5), v.last().copied())
}

/// `cases` random geometries played open-loop, then the closed-loop
/// scenarios on `loop_seeds` seeds from `seed` (`bench_fidelity_loop`).
pub fn run(cases: usize, seed: u64, loop_seeds: u64) -> anyhow::Result<Value> {
    if cases == 0 {
        anyhow::bail!("--cases must be at least 1");
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut shaped, mut at_rest, mut point) =
        ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
    let (mut done, mut redrawn, mut met) = (0, 0, 0);
    while done < cases {
        let input = random_case(&mut rng);
        let static_model = SolveInput { part_dynamics: false, ..input.clone() };
        let mut as_points = static_model.clone();
        as_points.parts.iter_mut().for_each(|p| p.shape = ShapeInput::Point);
        let case_seed = seed.wrapping_add(done as u64);
        let (Some(a), Some(s), Some(b)) = (
            errors(&input, &input, case_seed)?,
            errors(&input, &static_model, case_seed)?,
            errors(&input, &as_points, case_seed)?,
        ) else {
            redrawn += 1;
            continue;
        };
        at_rest.0.extend(s.0);
        at_rest.1.extend(s.1);
        // Targets: force within 2 % + 0.005 μmg, i.e. error/(|f| + 0.005 μmg)
        // within 2 % at |f| ≫ 0.005 μmg; curl within 10 %.
        met += usize::from(a.0.iter().all(|&e| e <= 0.02) && a.1.iter().all(|&e| e <= 0.10));
        shaped.0.extend(a.0);
        shaped.1.extend(a.1);
        point.0.extend(b.0);
        point.1.extend(b.1);
        done += 1;
    }
    let (fm, fw) = summary(&mut shaped.0);
    let (cm, cw) = summary(&mut shaped.1);
    let (sfm, sfw) = summary(&mut at_rest.0);
    let (scm, scw) = summary(&mut at_rest.1);
    let (bfm, bfw) = summary(&mut point.0);
    let (bcm, bcw) = summary(&mut point.1);
    Ok(json!({
        "cases": cases,
        "seed": seed,
        "redrawn_saturated": redrawn,
        "cases_within_targets": met,
        "forces": shaped.0.len(),
        "curls": shaped.1.len(),
        "force_err_median": fm,
        "force_err_worst": fw,
        "curl_err_median": cm,
        "curl_err_worst": cw,
        "static_force_err_median": sfm,
        "static_force_err_worst": sfw,
        "static_curl_err_median": scm,
        "static_curl_err_worst": scw,
        "baseline_force_err_median": bfm,
        "baseline_force_err_worst": bfw,
        "baseline_curl_err_median": bcm,
        "baseline_curl_err_worst": bcw,
        "cycles": CYCLES,
        "closed_loop": crate::bench_fidelity_loop::run(&(seed..seed + loop_seeds).collect::<Vec<_>>())?,
    }))
}

pub fn to_text(v: &Value) -> String {
    let pct = |x: &Value| x.as_f64().map_or("—".into(), |x| format!("{:.2} %", 100.0 * x));
    format!(
        "{} cases ({} forces, {} curls; {} saturated draws skipped), {} within the targets\n\
         per-shape model, part dynamics: force error median {}, worst {}; curl error median {}, worst {}\n\
         per-shape model, parts at rest: force error median {}, worst {}; curl error median {}, worst {}\n\
         point model (the paper's):      force error median {}, worst {}; curl error median {}, worst {}\n{}",
        v["cases"],
        v["forces"],
        v["curls"],
        v["redrawn_saturated"],
        v["cases_within_targets"],
        pct(&v["force_err_median"]),
        pct(&v["force_err_worst"]),
        pct(&v["curl_err_median"]),
        pct(&v["curl_err_worst"]),
        pct(&v["static_force_err_median"]),
        pct(&v["static_force_err_worst"]),
        pct(&v["static_curl_err_median"]),
        pct(&v["static_curl_err_worst"]),
        pct(&v["baseline_force_err_median"]),
        pct(&v["baseline_force_err_worst"]),
        pct(&v["baseline_curl_err_median"]),
        pct(&v["baseline_curl_err_worst"]),
        crate::bench_fidelity_loop::to_text(&v["closed_loop"]),
    )
}
