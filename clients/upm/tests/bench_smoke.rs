//! The benches run and report well-formed figures (never judged against a
//! time: that is BENCHMARKS.md's job). `bench ipc` also exercises both
//! receiver modes of the core (event-driven and busy-polling) end to end,
//! and a planner's wake-up on the part states event in Rust and in Python.

mod common;

use std::process::Command;

fn summary_ok(name: &str, s: &serde_json::Value) {
    let v: Vec<f64> = ["p50", "p99", "p999", "max"].iter().map(|k| s[k].as_f64().expect(k)).collect();
    assert!(s["samples"].as_u64() > Some(0), "{name}: no samples: {s}");
    assert!(v[0] > 0.0 && v.windows(2).all(|w| w[0] <= w[1]), "{name}: percentiles not ordered: {s}");
}

#[test]
fn bench_ipc_reports_both_receiver_modes_against_their_references() {
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["bench", "ipc", "--quick", "--json"])
        .env("UPM_PYTHON", common::python_with_iceoryx2())
        .output()
        .expect("upm bench ipc");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    for key in [
        "upm_event",
        "raw_iceoryx2_event",
        "upm_spin",
        "raw_iceoryx2_busy_poll",
        "solver_pickup_event",
        "solver_pickup_spin",
        "planner_wake_rust",
        "planner_wake_python",
        "raw_iceoryx2_event_wake",
    ] {
        summary_ok(key, &v[key]);
    }
    assert!(v["planner_wake_python_run"]["iceoryx2"].as_str().is_some_and(|s| s.starts_with("0.10.")), "{v}");
    for key in [
        "ratio_p99_event",
        "ratio_p99_spin",
        "ratio_p50_planner_wake_rust_vs_raw_event",
        "ratio_p50_planner_wake_python_vs_raw_event",
    ] {
        assert!(v[key].as_f64().is_some_and(|r| r.is_finite() && r > 0.0), "{key}: {v}");
    }
}

#[test]
fn bench_sort_reports_time_to_sort_per_seed_and_refuses_other_planners() {
    let upm = || Command::new(env!("CARGO_BIN_EXE_upm"));
    let out = upm()
        .args(["bench", "sort", "--seeds", "3", "--first-seed", "5", "--quick", "--json"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("upm bench sort");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let runs = v["runs"].as_array().expect("runs");
    let seeds: Vec<u64> = runs.iter().filter_map(|r| r["seed"].as_u64()).collect();
    assert_eq!(seeds, [5, 6, 7]);
    let sorted = runs.iter().filter(|r| r["time_to_sort_s"].is_number()).count();
    assert_eq!(v["sorted_fraction"].as_f64(), Some(sorted as f64 / 3.0), "{v}");
    // A seed not sorted in time ranks last: the maximum is then null, and
    // the median (the second of three) once two are unsorted.
    assert_eq!(v["max_s"].is_null(), sorted < 3, "{v}");
    assert_eq!(v["median_s"].is_null(), sorted < 2, "{v}");
    for r in runs {
        assert!(r["time_to_sort_s"].as_f64().is_none_or(|t| (0.0..=30.0).contains(&t)), "{r}");
        assert!(r["collisions"].as_u64().is_some(), "{r}");
    }
    // The paper's planner on the same seeds, in the same run.
    let base = &v["baseline"];
    assert_eq!((v["planner"].as_str(), base["planner"].as_str()), (Some("sort"), Some("sort_paper")), "{v}");
    let base_seeds: Vec<u64> =
        base["runs"].as_array().expect("runs").iter().filter_map(|r| r["seed"].as_u64()).collect();
    assert_eq!(base_seeds, [5, 6, 7]);
    assert_eq!(v["baseline_median_s"], base["median_s"], "{v}");
    for key in ["median_s", "p90_s", "max_s", "sorted_fraction", "collisions_median", "baseline_median_s"] {
        assert!(v.get(key).is_some(), "{key} missing: {v}");
    }
    let out = upm()
        .args(["bench", "sort", "--scenario", "track", "--seeds", "1", "--quick"])
        .output()
        .expect("upm");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("needs a scenario whose planner is sort"), "{err}");
}

#[test]
fn bench_fidelity_reports_both_models_on_the_same_cases() {
    let run = |seed: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_upm"))
            .args(["bench", "fidelity", "--quick", "--seed", seed, "--json"])
            .output()
            .expect("upm bench fidelity");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice::<serde_json::Value>(&out.stdout).expect("json")
    };
    let v = run("7");
    assert_eq!(v["cases"], 3, "{v}");
    assert!(v["forces"].as_u64() >= Some(3), "{v}");
    for model in ["", "baseline_"] {
        let (median, worst) = (&v[format!("{model}force_err_median")], &v[format!("{model}force_err_worst")]);
        assert!(median.as_f64().zip(worst.as_f64()).is_some_and(|(m, w)| 0.0 <= m && m <= w), "{v}");
    }
    // Curl keys exist; null when no case asked a curl.
    for key in ["curl_err_median", "curl_err_worst", "baseline_curl_err_worst"] {
        assert!(v[key].is_null() || v[key].as_f64().is_some_and(|e| e >= 0.0), "{key}: {v}");
    }
    assert_eq!(v, run("7"), "same seed, same figures");
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["bench", "fidelity", "--cases", "0", "--json"])
        .output()
        .expect("upm bench fidelity");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--cases must be at least 1"));
}

#[test]
fn bench_calibration_reports_nominal_and_calibrated_on_the_same_truths() {
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["bench", "calibration", "--quick", "--seed", "3", "--json"])
        .output()
        .expect("upm bench calibration");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["cases"], 2, "{v}");
    for key in [
        "nominal_force_err_median",
        "calibrated_force_err_median",
        "calibrated_force_err_worst",
        "nominal_track_rms_pct",
        "calibration_rig_s",
        "model_floor_force_err_median",
        "adapted_track_rms_pct",
        "both_track_rms_pct",
        "adapted_scale_err_median",
        "plate_mass_estimate_err_median",
        "nominal_push_direction_err_deg",
        "calibrated_push_direction_err_deg",
    ] {
        assert!(v[key].as_f64().is_some_and(|x| x >= 0.0), "{key}: {v}");
    }
    let (median, worst) = (&v["calibrated_force_err_median"], &v["calibrated_force_err_worst"]);
    assert!(median.as_f64().zip(worst.as_f64()).is_some_and(|(m, w)| m <= w), "{v}");
    assert_eq!(v["runs"].as_array().map(Vec::len), Some(2), "{v}");
    // The feed-forward's plate, as the measurement played it, is bounded.
    for run in v["runs"].as_array().into_iter().flatten() {
        let s = &run["worst_geometry"]["inertia_scale"];
        assert!((0..2).all(|i| s[i].as_f64().is_some_and(|x| (0.5..=2.0).contains(&x))), "{run}");
    }
}
