//! `upm bench line --quick` runs its three feed runs and reports every
//! figure with non-zero picks (never judged against a time: that is
//! BENCHMARKS.md's job).

use std::process::Command;

#[test]
fn bench_line_reports_picks_round_trips_ready_latency_and_churn() {
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["bench", "line", "--quick", "--json"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("upm bench line");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let t = &v["throughput"];
    for run in ["external", "builtin"] {
        assert!(t[run]["picked"].as_u64().is_some_and(|n| n > 0), "{run} picked nothing: {v}");
        assert!(t[run]["motor_p99_us"].as_f64().is_some_and(|p| p > 0.0), "{run}: {v}");
    }
    assert!(t["ratio_picked"].as_f64().is_some_and(|r| r.is_finite() && r > 0.0), "{v}");
    let rtt = &v["picked_call"]["round_trip"];
    assert_eq!(rtt["samples"], t["external"]["picked"], "every accepted call is a pick: {v}");
    assert!(rtt["p50_ms"].as_f64().is_some_and(|p| p > 0.0) && rtt["p99_ms"].is_number(), "{v}");
    let ready = &v["ready"];
    assert!(ready["from_feed_received"]["samples"].as_u64().is_some_and(|n| n > 0), "{v}");
    assert!(ready["from_feed_received"]["p99_ms"].is_number(), "{v}");
    assert!(ready["revised_publishing_interval_ms"].is_number(), "{v}");
    assert!(ready["revised_sampling_interval_ms"].is_number(), "{v}");
    let churn = &v["churn"];
    let c = &churn["clients"];
    assert_eq!(c["clients"], 20, "{v}");
    assert_eq!(c["opcua_ok"].as_u64().unwrap_or(0) + c["opcua_failed"].as_u64().unwrap_or(0), 10, "{v}");
    assert_eq!(c["modbus_ok"].as_u64().unwrap_or(0) + c["modbus_failed"].as_u64().unwrap_or(0), 10, "{v}");
    // The servers still answer after the churn.
    assert_eq!(c["after"]["opcua_state"], "running", "{v}");
    assert_eq!(c["after"]["modbus_state"], 1, "{v}");
    for k in ["run", "without", "no_line"] {
        assert!(churn[k]["motor_p99_us"].as_f64().is_some_and(|p| p > 0.0), "{k}: {v}");
    }
    assert!(v["host"]["kernel"].is_string(), "{v}");
}
