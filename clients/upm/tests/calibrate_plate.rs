//! `upm calibrate plate` against simulated plates whose truth it cannot
//! read: in lock-step and with real processes, what it finds, what it
//! refuses, and what the core and planner make of the file.

use std::path::PathBuf;
use std::process::Command;

use rig_config::PlateCalibration;
use upm_calibrate::ExciteParams;
use upm_commands::config::truth::TruthSection;
use upm_commands::scenario::{Scenario, resolve};

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("upm-calplate-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("dir");
    d
}

fn calibrated(truth: &str) -> PlateCalibration {
    let sc = Scenario::load(&resolve("calibrate")).expect("scenario");
    let mut config = sc.config(1, "unused_").expect("config");
    config.sim.truth = TruthSection::Preset(truth.into());
    upm_commands::calibrate_plate::lockstep(&config, ExciteParams::default()).expect("calibration")
}

fn scale(c: &PlateCalibration, class: u32) -> f64 {
    c.class_friction.iter().find(|f| f.class == class).map_or(f64::NAN, |f| f.scale)
}

#[test]
fn a_worn_plate_is_found_worn_and_a_nominal_one_nominal() {
    // The worn preset: class 0 at 1.0, class 1 at 0.8, the map's u² and v²
    // terms 0.15 (μ 10 % low in the middle, 25 % high at the corners).
    let worn = calibrated("worn");
    assert!(
        (scale(&worn, 0) - 1.0).abs() < 0.03 && (scale(&worn, 1) - 0.8).abs() < 0.03,
        "{:?}",
        worn.class_friction
    );
    assert!(
        (worn.friction_map[3] - 0.15).abs() < 0.04 && (worn.friction_map[4] - 0.15).abs() < 0.04,
        "{:?}",
        worn.friction_map
    );
    let nominal = calibrated("nominal");
    assert!(
        (scale(&nominal, 0) - 1.0).abs() < 0.02 && (scale(&nominal, 1) - 1.0).abs() < 0.02,
        "{:?}",
        nominal.class_friction
    );
    assert!(nominal.friction_map.iter().all(|c| c.abs() < 0.04), "{:?}", nominal.friction_map);
    for r in 0..3 {
        for c in 0..3 {
            let want = if r == c { 1.0 } else { 0.0 };
            assert!((nominal.twist_correction[r][c] - want).abs() < 0.03, "{:?}", nominal.twist_correction);
        }
    }
    // The same truth and seed give the same file.
    assert_eq!(calibrated("worn"), worn);
}

/// A plate built off its model (random truth 2011: the bench's tolerances,
/// one of the 20 the fit's prior was chosen on): the fitted correction
/// turns its pushes closer to the model's than no correction does
/// (measured 0.59° against 1.13°).
#[test]
fn a_plate_built_off_its_model_turns_closer_to_it_after_calibration() {
    let sc = Scenario::load(&resolve("calibrate")).expect("scenario");
    let mut config = sc.config(1, "unused_").expect("config");
    config.sim.truth = TruthSection::Preset("random:2011".into());
    // On the physics the bench judges by: at the scenario's 16 substeps the
    // simulator's own error turns this plate's fit (1.36° corrected).
    config.sim.config.substeps = upm_paper::validate::MEASURE_SUBSTEPS;
    let cal = upm_commands::calibrate_plate::lockstep(&config, ExciteParams::default()).expect("calibration");
    let [nominal, corrected] = upm_bench::bench_calibration::turning_err_deg(&config, &cal).expect("turning");
    eprintln!("random:2011 turning off the truth's: {nominal:.3}° uncorrected, {corrected:.3}° corrected");
    assert!(corrected < 0.7 * nominal, "{corrected}° corrected against {nominal}° uncorrected");
}

#[test]
fn the_core_loads_the_file_and_refuses_one_from_another_rig_and_the_planner_divides_by_friction() {
    let d = dir("load");
    let file = d.join("plate.toml");
    let cal = calibrated("worn");
    cal.write_atomically(&file).expect("write");
    let sc = Scenario::load(&resolve("track")).expect("scenario");
    let mut config = sc.config(1, "unused_").expect("config");
    config.calibration.file = Some(file.clone());
    let params = config.core_params("rig.toml").expect("core params");
    assert_eq!(params.twist_correction, Some(cal.twist_correction));
    // The core's part-dynamics correction reads the same friction the
    // planner divides by, everywhere (on and off the plate, any class).
    assert!(!params.part_friction.is_uniform());
    for class in 0..4u32 {
        for (x, y) in [(-0.9, 0.45), (0.0, 0.0), (0.37, -0.21), (3.0, -2.0), (-40.0, 9.0)] {
            let (core, planner) = (params.part_friction.scale(class, x, y), cal.friction_scale(class, x, y));
            assert!((core - planner).abs() < 1e-12, "class {class} at ({x}, {y}): {core} against {planner}");
        }
    }
    // The planner (which checks the file itself, not the rig: it does not
    // know the centers) asks for f / s where friction is μ·s.
    let loaded = PlateCalibration::load(&file).expect("load");
    let mut inner = config.planner.build().expect("planner");
    let mut wrapped = upm_planner::calibrated::on_plate(&config.planner, Some(loaded)).expect("planner");
    let mut states = ipc_types::PartStates::new();
    for (id, x, class) in [(1u32, -0.65, 0u32), (2, 0.25, 1)] {
        let _ = states.push(ipc_types::PartState { id, class, x, y: -0.15, ..ipc_types::PartState::ZERO });
    }
    let (mut a, mut b) = (ipc_types::ForceRequest::new(), ipc_types::ForceRequest::new());
    assert!(inner.plan(&states, 0.0, &mut a) && wrapped.plan(&states, 0.0, &mut b));
    for (ea, eb) in a.entries().iter().zip(b.entries()) {
        let p = states.parts().iter().find(|p| p.id == ea.part_id).expect("part");
        let s = cal.friction_scale(p.class, p.x, p.y);
        assert!((eb.fx * s - ea.fx).abs() < 1e-12 && (eb.fy * s - ea.fy).abs() < 1e-12);
    }
    // A file made on a rig with other centers.
    let mut other = cal.clone();
    other.centers[3][0] += 0.01;
    other.write_atomically(&file).expect("write");
    let e = config.core_params("rig.toml").expect_err("other rig").to_string();
    assert!(e.contains("calibration.file") && e.contains("centers[3]"), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn too_few_parts_is_one_line_and_no_file() {
    let d = dir("few");
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["calibrate", "plate", "--scenario", "track", "--lockstep", "--out"])
        .arg(d.join("plate.toml"))
        .output()
        .expect("upm");
    assert!(!out.status.success());
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(said.trim_end(), "upm: error: too few parts on the plate: 2 seen, the fit needs at least 3");
    assert!(!d.join("plate.toml").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn real_processes_calibrate_a_worn_plate_and_keep_the_old_file() {
    let d = dir("live");
    let file = d.join("plate.toml");
    let old = calibrated("nominal");
    old.write_atomically(&file).expect("old file");
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .current_dir(&d)
        .args(["calibrate", "plate", "--scenario"])
        .arg(resolve("calibrate"))
        .args(["--truth", "worn", "--out"])
        .arg(&file)
        .output()
        .expect("upm");
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{said}");
    let new = PlateCalibration::load(&file).expect("new file");
    assert!((scale(&new, 1) / scale(&new, 0) - 0.8).abs() < 0.04, "{:?}", new.class_friction);
    assert!(new.report.rig_seconds <= 60.0);
    let mut kept = file.clone().into_os_string();
    kept.push(".previous");
    assert_eq!(PlateCalibration::load(&PathBuf::from(kept)).expect("kept"), old);
    let _ = std::fs::remove_dir_all(&d);
}
