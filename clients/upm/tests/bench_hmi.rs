//! `upm bench hmi --quick` runs a feed rig without and with pages open and
//! reports both runs' core figures and what the pages received (never
//! judged against a time: that is BENCHMARKS.md's job).

use std::process::Command;

#[test]
fn bench_hmi_reports_both_runs_and_every_page_is_served() {
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["bench", "hmi", "--quick", "--json"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("upm bench hmi");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    for (k, pages) in [("without", 0), ("with", 10)] {
        let runs = v["runs"][k].as_array().unwrap_or_else(|| panic!("{k}: {v}"));
        assert_eq!(runs.len(), 1, "{k}: {v}");
        let r = &runs[0];
        assert_eq!(r["pages"], pages, "{k}: {v}");
        assert!(r["motor_p99_us"].as_f64().is_some_and(|p| p > 0.0), "{k}: {v}");
        assert!(r["solver_p99_us"].as_f64().is_some_and(|p| p > 0.0), "{k}: {v}");
        assert_eq!(r["hmi_restarts"], 0, "{k}: {v}");
        assert_eq!(r["pages_failed"], 0, "{k}: {v}");
    }
    // Ten pages at 10 updates a second over a 20 s run.
    let updates = v["runs"]["with"][0]["updates_received"].as_u64().unwrap_or(0);
    assert!(updates >= 10 * 50, "{updates} updates: {v}");
    assert!(v["ratio_motor_p99"].as_f64().is_some_and(f64::is_finite), "{v}");
    assert!(v["host"]["kernel"].is_string(), "{v}");
}
