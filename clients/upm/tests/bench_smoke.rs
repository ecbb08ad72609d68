//! The benches run and report well-formed figures (never judged against a
//! time: that is BENCHMARKS.md's job). `bench ipc` also exercises both
//! receiver modes of the core (event-driven and busy-polling) end to end.

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
    ] {
        summary_ok(key, &v[key]);
    }
    for key in ["ratio_p99_event", "ratio_p99_spin"] {
        assert!(v[key].as_f64().is_some_and(|r| r.is_finite() && r > 0.0), "{key}: {v}");
    }
}
