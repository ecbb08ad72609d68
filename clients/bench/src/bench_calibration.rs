//! `upm bench calibration`: how far the model is from a plate that is not
//! what it says, and how much `upm calibrate plate` brings back. Each case
//! draws a hidden truth (`random:SEED`: actuators off by up to 10 mm and
//! 5 mrad, sensors by up to 5 %, the plate's mass by 10 %, friction 10–30 %
//! uneven over the plate and 0.7–1.3 per part class), calibrates in
//! lock-step on `scenarios/calibrate.toml` (the track rig with ten parts),
//! then measures, in the same run:
//! - force error at random part positions as `upm validate` measures it
//!   (one cycle from rest, played on the simulator with the truth), solved
//!   from the nominal model and from the calibrated one;
//! - `track`'s RMS distance to its path (percent of the path's length),
//!   with the nominal model and with the calibration loaded by core and
//!   planner.
//!
//! - the same with online friction adaptation in the planner
//!   (`upm_planner::adaptive`), alone and on top of the calibration, and
//!   how close its learnt scales come to the truth's.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use upm_commands::config::Config;
use upm_commands::config::truth::TruthSection;
use upm_commands::scenario::{Scenario, resolve};
use upm_paper::solve_json::{PartInput, ShapeInput, SolveInput, solve};
use upm_paper::validate::{ValidateSetup, measure};

/// Random geometries per case, and cycles each is played for.
const GEOMETRIES: usize = 6;
const CYCLES: usize = 2;
/// Parts are placed anywhere in ±`REGION` (m); the turning is judged there.
const REGION: [f64; 2] = [0.8, 0.4];
/// Solve with the velocity parts pick up through the cycle (issue 25's
/// correction), as the best model the controller has.
const PART_DYNAMICS: bool = true;
/// The core scales its feed-forward to the plate the drives show
/// (`[motion] adapt_plate_inertia`, on by default with the simulator); each geometry is
/// measured after this many cycles of it, as a core that has been
/// running that request would play it.
const INERTIA_WARMUP: usize = 12;

/// The truth's scale of part class `class` and the simulator's settings.
fn plate_of(
    config: &Config,
) -> anyhow::Result<(drivers::SimConfig, upm_commands::config::truth::ResolvedTruth)> {
    let sim = config.sim_config("bench")?;
    let truth =
        config.sim.truth.resolve(sim.rig.count, config.plate.half_extent).map_err(anyhow::Error::msg)?;
    Ok((sim, truth))
}

/// Both plates play every center up to the same |k|: the least that the
/// nominal and the corrected commands allow.
fn common_k_max(config: &Config, calibration: &rig_config::PlateCalibration) -> anyhow::Result<f64> {
    let core = config.core_params("bench")?;
    let corrected =
        rt_core::CoreParams { twist_correction: Some(calibration.twist_correction), ..core.clone() };
    Ok(core
        .playable_k_bounds()
        .map_err(|e| anyhow::anyhow!("{e}"))?
        .into_iter()
        .chain(corrected.playable_k_bounds().map_err(|e| anyhow::anyhow!("{e}"))?)
        .fold(core.motion.k_max, f64::min))
}

/// Force errors (relative to the request plus 0.005 μmg) of one geometry, with |k| ≤ `k_max`,
/// solved from the nominal model and from `calibration`, and (the model's
/// own floor) from the nominal model on a plate that is exactly nominal.
fn force_errors(
    config: &Config,
    calibration: &rig_config::PlateCalibration,
    k_max: f64,
    rng: &mut ChaCha8Rng,
    seed: u64,
) -> anyhow::Result<Option<([Vec<f64>; 3], Value)>> {
    let core = config.core_params("bench")?;
    let (sim, truth) = plate_of(config)?;
    let count = rng.random_range(1..=4usize);
    let mut parts: Vec<PartInput> = Vec::new();
    let mut classes = Vec::new();
    while parts.len() < count {
        let position = [rng.random_range(-REGION[0]..REGION[0]), rng.random_range(-REGION[1]..REGION[1])];
        if parts.iter().any(|p| (p.position[0] - position[0]).hypot(p.position[1] - position[1]) < 0.1) {
            continue;
        }
        let f = rng.random_range(0.002..0.01);
        let a = rng.random_range(0.0..core::f64::consts::TAU);
        parts.push(PartInput {
            position,
            force: Some([f * a.cos(), f * a.sin()]),
            shape: ShapeInput::Point,
            curl: None,
            friction: None,
        });
        classes.push(rng.random_range(0..2u32));
    }
    let nominal = SolveInput {
        mu_m_g: core.plate.mu_m_g,
        centers: core.plate.centers.clone(),
        parts,
        curls: Vec::new(),
        k_max: Some(k_max),
        part_dynamics: PART_DYNAMICS,
    };
    // The calibrated model asks each part for f / s where friction is μ·s,
    // and its part dynamics slides it with that friction.
    let mut calibrated = nominal.clone();
    for (p, &class) in calibrated.parts.iter_mut().zip(&classes) {
        let s = calibration.friction_scale(class, p.position[0], p.position[1]);
        p.force = p.force.map(|f| [f[0] / s, f[1] / s]);
        p.friction = Some(s);
    }
    // Each part's material; the simulator adds the map where it stands.
    let friction: Vec<f64> = classes.iter().map(|&c| truth.class_friction(c)).collect();
    let setup = ValidateSetup {
        motion: core.motion,
        sim: drivers::SimConfig { collisions: false, substeps: upm_paper::validate::MEASURE_SUBSTEPS, ..sim },
        twist_correction: None,
        inertia_warmup: core.inertia_adaptation.is_some().then_some(INERTIA_WARMUP),
    };
    let exact = ValidateSetup {
        sim: drivers::SimConfig { truth: drivers::PlateTruth::NOMINAL, ..setup.sim },
        ..setup
    };
    let mut errors = Vec::new();
    let mut inertia_scale = [1.0; 2];
    for (model, setup, friction) in [
        (&nominal, setup, &friction[..]),
        (
            &calibrated,
            ValidateSetup { twist_correction: Some(calibration.twist_correction), ..setup },
            &friction[..],
        ),
        (&nominal, exact, &[][..]),
    ] {
        let out = solve(model)?;
        if out.saturated || out.residual > 1e-9 {
            return Ok(None);
        }
        let order: Vec<u16> = out.order.iter().map(|&j| j as u16).collect();
        let m = measure(&nominal, &out.k, &order, CYCLES, seed, &setup, friction)?;
        if setup.twist_correction.is_some() {
            inertia_scale = m.inertia_scale;
        }
        let mu = nominal.mu_m_g;
        errors.push(
            nominal
                .parts
                .iter()
                .zip(&m.forces)
                .filter_map(|(p, s)| p.force.map(|f| upm_paper::solve_json::relative_force_error(f, *s, mu)))
                .collect::<Vec<f64>>(),
        );
    }
    let floor = errors.pop().unwrap_or_default();
    let calibrated = errors.pop().unwrap_or_default();
    let nominal_err = errors.pop().unwrap_or_default();
    // The geometry as played, to find a bad case again.
    let parts: Vec<Value> = nominal
        .parts
        .iter()
        .zip(&classes)
        .zip(&calibrated)
        .map(|((p, c), e)| json!({ "position": p.position, "force": p.force, "class": c, "calibrated_err": e }))
        .collect();
    // What the feed-forward took the plate to be, against what it is.
    let geometry = json!({
        "seed": seed,
        "parts": parts,
        "inertia_scale": inertia_scale,
        "truth_plate_mass": 1.0 + truth.plate.plate_mass_error,
    });
    Ok(Some(([nominal_err, calibrated, floor], geometry)))
}

/// `track`'s RMS distance to its path, percent of the path's length; with
/// `adapt`, also each part's learnt friction scale against the truth's
/// where the part ended (relative error).
fn track_rms_pct(
    config: &Config,
    calibration: Option<rig_config::PlateCalibration>,
    adapt: bool,
    seconds: f64,
) -> anyhow::Result<(f64, Vec<f64>)> {
    let sc = Scenario::load(&resolve("track"))?;
    let mut planner_config = config.planner.clone();
    planner_config.drive_mut().adapt_friction = adapt;
    let mut planner =
        upm_planner::calibrated::on_plate(&planner_config, calibration).map_err(anyhow::Error::msg)?;
    let r = upm_commands::closed_loop::run(config, planner.as_mut(), seconds)?;
    let m = sc.evaluate(config, &r.trails);
    let rms = m["tracking_rms_m"].as_f64().unwrap_or(f64::NAN);
    let path = m["path_length_m"].as_f64().unwrap_or(f64::NAN);
    let (_, truth) = plate_of(config)?;
    let mut scale_errors = Vec::new();
    for (id, believed) in planner.friction_estimates() {
        let Some((class, q)) = r.trails.parts.get(&id).and_then(|t| t.points.last().map(|q| (t.class, *q)))
        else {
            continue;
        };
        let real = truth.friction_at(class, q[1], q[2]);
        scale_errors.push((believed - real).abs() / real);
    }
    Ok((100.0 * rms / path, scale_errors))
}

/// |estimated − true| / true plate mass, per run that has both.
fn mass_err(rows: &[Value]) -> Vec<f64> {
    rows.iter()
        .filter_map(|r| {
            let g = &r["worst_geometry"];
            let (estimate, truth) = (g["inertia_scale"][0].as_f64()?, g["truth_plate_mass"].as_f64()?);
            Some((estimate - truth).abs() / truth)
        })
        .collect()
}

/// How far a twist correction leaves the plate's pushes from the model's:
/// RMS over every center and a 9 × 5 grid over ±[`REGION`] (where the
/// bench puts parts) of the angle between R90(P − C′), C′ the center the
/// plate really turns about when commanded through `correction`, and
/// R90(P − C) (degrees); `truth` is the plate's own map of commanded to
/// true twist (`drivers::PlateTruth::twist_map`, the evaluator's
/// reference). Independent of which geometries are drawn.
fn push_direction_err_deg(centers: &[[f64; 2]], truth: [[f64; 3]; 3], correction: [[f64; 3]; 3]) -> f64 {
    let plate =
        nalgebra::Matrix3::from_fn(|r, c| truth[r][c]) * nalgebra::Matrix3::from_fn(|r, c| correction[r][c]);
    let (mut ss, mut n) = (0.0, 0.0);
    for c in centers {
        let xi = plate * nalgebra::Vector3::new(c[1], -c[0], 1.0);
        let turned = [-xi[1] / xi[2], xi[0] / xi[2]];
        for i in 0..9 {
            for j in 0..5 {
                let p = [REGION[0] * (i as f64 / 4.0 - 1.0), REGION[1] * (j as f64 / 2.0 - 1.0)];
                let dir = |q: [f64; 2]| (p[0] - q[0]).atan2(q[1] - p[1]);
                let d = dir(turned) - dir(*c);
                let e = d.sin().atan2(d.cos());
                ss += e * e;
                n += 1.0;
            }
        }
    }
    (ss / n).sqrt().to_degrees()
}

/// The turning `calibration` leaves on `config`'s simulated plate against
/// the truth's own ([`push_direction_err_deg`]): uncorrected, corrected.
pub fn turning_err_deg(
    config: &Config,
    calibration: &rig_config::PlateCalibration,
) -> anyhow::Result<[f64; 2]> {
    let (sim, truth) = plate_of(config)?;
    let exact = truth.plate.twist_map(&sim.rig).ok_or_else(|| anyhow::anyhow!("sim.rig: not a valid rig"))?;
    let identity = core::array::from_fn(|r| core::array::from_fn(|c| if r == c { 1.0 } else { 0.0 }));
    Ok([identity, calibration.twist_correction]
        .map(|m| push_direction_err_deg(&calibration.centers, exact, m)))
}

pub fn run(cases: usize, seed: u64, quick: bool) -> anyhow::Result<Value> {
    if cases == 0 {
        anyhow::bail!("--cases must be at least 1");
    }
    let calibrate = Scenario::load(&resolve("calibrate"))?;
    let track = Scenario::load(&resolve("track"))?;
    let track_s = if quick { 20.0 } else { track.duration_s };
    let dir = std::env::temp_dir().join(format!("upm-bench-calibration-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut nominal_f, mut calibrated_f, mut floor_f) = (Vec::new(), Vec::new(), Vec::new());
    let (mut scale_err, mut both_scale_err) = (Vec::new(), Vec::new());
    let mut rows = Vec::new();
    let mut rig_s = Vec::new();
    let mut observations = Vec::new();
    for case in 0..cases {
        let truth =
            TruthSection::Preset(format!("random:{}", seed.wrapping_mul(1000).wrapping_add(case as u64)));
        let mut cal_config = calibrate.config(seed.wrapping_add(case as u64), "unused_")?;
        cal_config.sim.truth = truth.clone();
        // Calibrated on the physics it is judged by.
        cal_config.sim.config.substeps = upm_paper::validate::MEASURE_SUBSTEPS;
        let cal = match upm_commands::calibrate_plate::lockstep(
            &cal_config,
            upm_calibrate::ExciteParams::default(),
        ) {
            Ok(c) => c,
            Err(e) => {
                rows.push(json!({ "case": case, "truth": truth, "refused": e.to_string() }));
                continue;
            }
        };
        rig_s.push(cal.report.rig_seconds);
        observations.push(f64::from(cal.report.observations));
        let (mut nf, mut cf, mut ff) = (Vec::new(), Vec::new(), Vec::new());
        let (mut drawn, mut played) = (0, 0);
        let mut worst_geometry = (f64::NEG_INFINITY, Value::Null);
        let k_max = common_k_max(&cal_config, &cal)?;
        let push_err = turning_err_deg(&cal_config, &cal)?;
        while played < GEOMETRIES && drawn < 4 * GEOMETRIES {
            drawn += 1;
            if let Some(([n, c, f], geometry)) =
                force_errors(&cal_config, &cal, k_max, &mut rng, seed.wrapping_add(drawn as u64))?
            {
                played += 1;
                let worst = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                if worst > worst_geometry.0 {
                    worst_geometry = (worst, geometry);
                }
                nf.extend(n);
                cf.extend(c);
                ff.extend(f);
            }
        }
        let mut track_config = track.config(seed.wrapping_add(case as u64), "unused_")?;
        track_config.sim.truth = truth.clone();
        let (nominal_track, _) = track_rms_pct(&track_config, None, false, track_s)?;
        let (adapted_track, adapt_err) = track_rms_pct(&track_config, None, true, track_s)?;
        let file = dir.join(format!("case{case}.toml"));
        cal.write_atomically(&file).map_err(anyhow::Error::msg)?;
        track_config.calibration.file = Some(file);
        let (calibrated_track, _) = track_rms_pct(&track_config, Some(cal.clone()), false, track_s)?;
        let (both_track, both_err) = track_rms_pct(&track_config, Some(cal.clone()), true, track_s)?;
        scale_err.extend(adapt_err.iter().copied());
        both_scale_err.extend(both_err.iter().copied());
        rows.push(json!({
            "case": case,
            "truth": truth,
            "nominal_force_err_median": upm_stats::median(&mut nf.clone()),
            "nominal_push_direction_err_deg": push_err[0],
            "calibrated_push_direction_err_deg": push_err[1],
            "calibrated_force_err_median": upm_stats::median(&mut cf.clone()),
            "calibrated_force_err_worst": cf.iter().copied().fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x)))),
            "nominal_track_rms_pct": nominal_track,
            "calibrated_track_rms_pct": calibrated_track,
            "adapted_track_rms_pct": adapted_track,
            "both_track_rms_pct": both_track,
            "report": serde_json::to_value(&cal.report)?,
            "worst_geometry": worst_geometry.1,
            "class_friction": cal.class_friction.iter().map(|f| f.scale).collect::<Vec<f64>>(),
            "friction_map": cal.friction_map,
        }));
        nominal_f.extend(nf);
        calibrated_f.extend(cf);
        floor_f.extend(ff);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let col = |key: &str| -> Vec<f64> { rows.iter().filter_map(|r| r[key].as_f64()).collect() };
    let worst =
        |v: &[f64]| v.iter().copied().fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m: f64| m.max(x))));
    let (nt, ct) = (col("nominal_track_rms_pct"), col("calibrated_track_rms_pct"));
    let (at, bt) = (col("adapted_track_rms_pct"), col("both_track_rms_pct"));
    // The friction fit's least squares at the size these calibrations had
    // (two part classes, as on the calibrate rig).
    let fit_rows = upm_stats::median(&mut observations);
    let least_squares = crate::bench_least_squares::run(
        fit_rows.map_or(600, |r| r as usize),
        2,
        if quick { 0.05 } else { 0.5 },
    )?;
    Ok(json!({
        "cases": cases,
        "seed": seed,
        "track_seconds": track_s,
        "least_squares": least_squares,
        "refused": rows.iter().filter(|r| !r["refused"].is_null()).count(),
        "nominal_force_err_median": upm_stats::median(&mut nominal_f.clone()),
        "nominal_force_err_worst": worst(&nominal_f),
        "calibrated_force_err_median": upm_stats::median(&mut calibrated_f.clone()),
        "calibrated_force_err_worst": worst(&calibrated_f),
        "model_floor_force_err_median": upm_stats::median(&mut floor_f.clone()),
        // RMS angle between the plate's pushes and the model's over every
        // center and the bench's region (degrees), each truth's, median.
        "nominal_push_direction_err_deg": upm_stats::median(&mut col("nominal_push_direction_err_deg")),
        "calibrated_push_direction_err_deg": upm_stats::median(&mut col("calibrated_push_direction_err_deg")),
        "calibrated_push_direction_err_deg_worst": worst(&col("calibrated_push_direction_err_deg")),
        "model_floor_force_err_worst": worst(&floor_f),
        "nominal_track_rms_pct": upm_stats::median(&mut nt.clone()),
        "nominal_track_rms_pct_worst": worst(&nt),
        "calibrated_track_rms_pct": upm_stats::median(&mut ct.clone()),
        "calibrated_track_rms_pct_worst": worst(&ct),
        "adapted_track_rms_pct": upm_stats::median(&mut at.clone()),
        "adapted_track_rms_pct_worst": worst(&at),
        "both_track_rms_pct": upm_stats::median(&mut bt.clone()),
        "both_track_rms_pct_worst": worst(&bt),
        // The learnt friction scale against the truth's where each part
        // ended, relative: adaptation alone, and on top of the calibration.
        "adapted_scale_err_median": upm_stats::median(&mut scale_err.clone()),
        "both_scale_err_median": upm_stats::median(&mut both_scale_err.clone()),
        "calibration_rig_s": upm_stats::median(&mut rig_s.clone()),
        // The feed-forward's plate mass (at each truth's worst geometry)
        // against the truth's, relative.
        "plate_mass_estimate_err_median": upm_stats::median(&mut mass_err(&rows)),
        "runs": rows,
    }))
}

pub fn to_text(v: &Value) -> String {
    let fit = crate::bench_least_squares::to_text(&v["least_squares"]);
    let pct = |k: &str| v[k].as_f64().map_or("—".into(), |x| format!("{:.1} %", 100.0 * x));
    let num = |k: &str| v[k].as_f64().map_or("—".into(), |x| format!("{x:.2}"));
    format!(
        "{} hidden truths (seed {}), {} refused; calibration takes {} s of rig time\n\
         force error, median / worst: nominal {} / {}, calibrated {} / {} (the model on an exact plate: {} / {})\n\
         push direction against the plate's (RMS, median over truths): nominal {}°, calibrated {}° (worst {}°)\n\
         track RMS (% of path), median / worst: nominal {} / {}, calibrated {} / {}, adapted {} / {}, both {} / {}\n\
         learnt friction scale against the truth (median): adapted {}, both {}\n{fit}",
        v["cases"],
        v["seed"],
        v["refused"],
        num("calibration_rig_s"),
        pct("nominal_force_err_median"),
        pct("nominal_force_err_worst"),
        pct("calibrated_force_err_median"),
        pct("calibrated_force_err_worst"),
        pct("model_floor_force_err_median"),
        pct("model_floor_force_err_worst"),
        num("nominal_push_direction_err_deg"),
        num("calibrated_push_direction_err_deg"),
        num("calibrated_push_direction_err_deg_worst"),
        num("nominal_track_rms_pct"),
        num("nominal_track_rms_pct_worst"),
        num("calibrated_track_rms_pct"),
        num("calibrated_track_rms_pct_worst"),
        num("adapted_track_rms_pct"),
        num("adapted_track_rms_pct_worst"),
        num("both_track_rms_pct"),
        num("both_track_rms_pct_worst"),
        pct("adapted_scale_err_median"),
        pct("both_scale_err_median"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_push_direction_error_is_zero_only_for_the_truths_own_inverse() {
        let rig = upm_motion::RigParams::default();
        let centers = [[1.2, 0.2], [-0.2, 0.8], [-1.3, 0.0], [0.6, -0.7]];
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let nominal = drivers::PlateTruth::NOMINAL.twist_map(&rig).expect("rig");
        assert!(push_direction_err_deg(&centers, nominal, identity) < 1e-9);
        let worn = drivers::PlateTruth::worn().twist_map(&rig).expect("rig");
        let uncorrected = push_direction_err_deg(&centers, worn, identity);
        assert!(uncorrected > 0.1, "a worn plate turns elsewhere: {uncorrected}°");
        let m = nalgebra::Matrix3::from_fn(|r, c| worn[r][c]).try_inverse().expect("invertible");
        // Any scale of the exact inverse turns about the same centers.
        let exact = core::array::from_fn(|r| core::array::from_fn(|c| 1.3 * m[(r, c)]));
        assert!(push_direction_err_deg(&centers, worn, exact) < 1e-9);
    }
}
