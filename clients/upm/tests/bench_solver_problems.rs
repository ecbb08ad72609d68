//! `upm bench solver --problems FILE` as a user runs it: one `upm solve`
//! input per line, a row per good line with every promised key, the
//! malformed line named by number, a non-zero exit, and UPM's bounded
//! optimum no worse than Clarabel's on the same problem.

use std::process::Command;

/// A saturated problem (forces far beyond what k_max allows).
fn saturated(parts: usize, centers: usize, gain: f64) -> String {
    let centers: Vec<String> = (0..centers)
        .map(|j| {
            let a = j as f64 * 2.399_963;
            let r = 1.2 + 0.3 * (j as f64 * 0.7).sin();
            format!("[{:.6},{:.6}]", r * a.cos(), 0.7 * r * a.sin())
        })
        .collect();
    let parts: Vec<String> = (0..parts)
        .map(|i| {
            let a = i as f64 * 2.399_963;
            let r = 0.5 * ((i as f64 + 0.5) / parts as f64).sqrt();
            format!(
                r#"{{"position":[{:.6},{:.6}],"force":[{:.6},{:.6}]}}"#,
                r * a.cos(),
                0.5 * r * a.sin(),
                gain * (i as f64).cos(),
                gain * (1.0 + i as f64).sin()
            )
        })
        .collect();
    format!(r#"{{"mu_m_g":0.1,"k_max":0.9,"centers":[{}],"parts":[{}]}}"#, centers.join(","), parts.join(","))
}

#[test]
fn every_good_line_gets_a_row_and_a_malformed_one_fails_the_run() {
    let dir = std::env::temp_dir().join(format!("upm_bench_problems_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("problems.jsonl");
    let text = format!("{}\n{{\"mu_m_g\": oops}}\n\n{}\n", saturated(3, 9, 0.05), saturated(10, 24, 0.05));
    std::fs::write(&file, text).expect("write problems");
    let out = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(["bench", "solver", "--quick", "--json", "--problems"])
        .arg(&file)
        .output()
        .expect("run upm");
    let _ = std::fs::remove_dir_all(&dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "a malformed line must fail the run");
    assert!(err.contains("line 2"), "the malformed line is named: {err}");
    assert!(!err.contains("panicked"), "{err}");
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON array on stdout");
    let rows = rows.as_array().expect("array");
    assert_eq!(rows.len(), 2, "one row per good line");
    for row in rows {
        for key in [
            "m",
            "n",
            "saturated",
            "upm_cold_p50_us",
            "upm_cold_p99_us",
            "upm_warm_p50_us",
            "reference_p50_us",
            "nalgebra_p50_us",
            "objective",
            "reference_objective",
        ] {
            assert!(row.get(key).is_some_and(|v| !v.is_null()), "{key} missing in {row}");
        }
        assert_eq!(row["saturated"], true, "{row}");
        assert_eq!(row["allocations"], 0, "{row}");
        assert_eq!(row["failed_solves"], 0, "{row}");
        let (upm, reference) = (
            row["objective"].as_f64().unwrap_or(f64::NAN),
            row["reference_objective"].as_f64().unwrap_or(f64::NAN),
        );
        assert!(upm <= reference * (1.0 + 1e-9), "UPM {upm} worse than Clarabel {reference}");
    }
}
