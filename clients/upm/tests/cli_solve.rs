//! The `upm` binary as users run it: the paper's examples, stdin, and every
//! kind of bad input exiting non-zero with one line that names the field.

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn upm(args: &[&str], stdin: Option<&str>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_upm"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn upm");
    if let Some(text) = stdin {
        child.stdin.take().expect("stdin").write_all(text.as_bytes()).expect("write");
    }
    drop(child.stdin.take());
    child.wait_with_output().expect("wait")
}

fn json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

/// Exit non-zero, exactly one stderr line, containing `needle`, no panic.
fn rejects(input: &str, needle: &str) {
    let out = upm(&["solve", "-"], Some(input));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "accepted: {input}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    assert!(err.contains(needle), "{err:?} does not name {needle:?} (input {input})");
    assert!(!err.contains("panicked"), "{err}");
    assert!(out.stdout.is_empty());
}

/// `saturated` says a bound keeps the request from being met; a bound
/// active while the request is met shows in `at_bound` alone.
#[test]
fn saturated_means_unmet_and_at_bound_counts_the_centers_at_their_bound() {
    let centers = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]];
    let ask = |force: [f64; 2]| {
        let input = format!(
            "{{\"mu_m_g\": 0.1, \"centers\": {centers:?}, \"parts\": [{{\"position\": [0.5, 0.0], \"force\": {force:?}}}]}}"
        );
        json(&upm(&["solve", "-"], Some(&input)))
    };
    let zero = ask([0.0, 0.0]);
    assert_eq!(
        (&zero["saturated"], &zero["at_bound"], &zero["residual"]),
        (&false.into(), &0.into(), &0.0.into())
    );
    // 98 % of the most the bounds (the validation rig's) allow, in the best
    // direction: only K near the box's corner gives it.
    let bounds: Vec<f64> =
        zero["k_bounds"].as_array().expect("k_bounds").iter().filter_map(|b| b.as_f64()).collect();
    let (most, d) = upm_solver::max_force_at(&centers, &bounds, 0.1, 0, 0.0, [0.5, 0.0]);
    let met = ask([0.98 * most * d[0], 0.98 * most * d[1]]);
    assert!(met["at_bound"].as_u64() >= Some(1), "{met}");
    assert_eq!(met["saturated"], false, "{met}");
    assert!(met["residual"].as_f64().is_some_and(|r| r < 1e-9 * most), "{met}");
    let beyond = ask([0.5, 0.0]);
    assert_eq!(beyond["saturated"], true, "{beyond}");
    assert!(beyond["at_bound"].as_u64() >= Some(1) && beyond["residual"].as_f64() > Some(0.1), "{beyond}");
}

#[test]
fn paper_3_1_from_a_file() {
    let v = json(&upm(&["solve", "examples/paper-3-1.json"], None));
    let k: Vec<f64> = v["k"].as_array().expect("k").iter().map(|x| x.as_f64().expect("num")).collect();
    for (got, want) in k.iter().zip([0.584, -0.389, 0.480, -0.0946]) {
        assert!((got - want).abs() <= 0.006, "k = {k:?}");
    }
    assert_eq!(v["order"], serde_json::json!([0, 2, 1, 3]));
    assert_eq!(v["rank"], 4);
    assert_eq!((&v["saturated"], &v["at_bound"]), (&false.into(), &0.into()));
    assert_eq!(v["iterations"], 0, "the exact path iterates not");
    assert!(v["solve_time_us"].as_f64().is_some_and(|t| t > 0.0), "solve_time_us: {}", v["solve_time_us"]);
    // The plate's four corners, alike by symmetry, play less than the
    // default k_max 0.95 on the validation rig (measured 0.75), and more
    // than this answer needs.
    let bounds: Vec<f64> =
        v["k_bounds"].as_array().expect("k_bounds").iter().filter_map(|x| x.as_f64()).collect();
    assert_eq!(bounds.len(), 4);
    assert!(bounds.iter().all(|&u| u == bounds[0] && u > 0.6 && u < 0.95), "{bounds:?}");
    assert_eq!(v["k_lowered"], serde_json::json!([0, 1, 2, 3]));
}

#[test]
fn a_bound_the_rig_cannot_play_is_lowered_and_named() {
    // k_max 1 is beyond the motion's 0.95 everywhere; a center 5 m out
    // swings the plate's far corner beyond the actuators' reach sooner.
    let input = r#"{"mu_m_g": 0.1, "k_max": 1.0, "centers": [[-1, -0.5], [1, 0.5], [5, 0]],
        "parts": [{"position": [0, 0], "force": [0.05, 0.02]}]}"#;
    let v = json(&upm(&["solve", "-"], Some(input)));
    assert_eq!(v["k_lowered"], serde_json::json!([0, 1, 2]), "{v}");
    let bounds: Vec<f64> =
        v["k_bounds"].as_array().expect("k_bounds").iter().filter_map(|x| x.as_f64()).collect();
    assert_eq!(bounds.len(), 3);
    assert!(bounds.iter().all(|&u| u > 0.0 && u < 1.0), "{bounds:?}");
    for (k, u) in v["k"].as_array().expect("k").iter().zip(&bounds) {
        assert!(k.as_f64().is_some_and(|k| k.abs() <= *u), "{k} beyond {u}");
    }
}

#[test]
fn paper_3_3_from_stdin() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/paper-3-3.json"))
        .expect("example");
    let v = json(&upm(&["solve", "-"], Some(&text)));
    assert_eq!(v["k"].as_array().expect("k").len(), 3);
    let curl = v["achieved"]["curls"][0].as_f64().expect("curl");
    assert!((curl + 0.05).abs() < 1e-6, "curl {curl}");
}

const GOOD: &str = r#"{"mu_m_g":0.1,"centers":[[-1,-0.5],[1,-0.5],[1,0.5],[-1,0.5]],
  "parts":[{"position":[0.5,0.0],"force":[0.01,0.01]}]}"#;

#[test]
fn the_good_input_used_below_is_accepted() {
    json(&upm(&["solve", "-"], Some(GOOD)));
}

#[test]
fn bad_inputs_exit_nonzero_with_one_line_naming_the_field() {
    rejects(&GOOD.replace("\"mu_m_g\":0.1", "\"mu_m_g\":null"), "mu_m_g");
    rejects(&GOOD.replace("\"mu_m_g\":0.1", "\"mu_m_g\":\"0.1\""), "mu_m_g");
    rejects(&GOOD.replace("\"mu_m_g\":0.1", "\"mu_m_g\":0"), "mu_m_g");
    rejects(&GOOD.replace("\"mu_m_g\":0.1", "\"mu_m_g\":-1"), "mu_m_g");
    rejects(&GOOD.replace("[0.01,0.01]", "[null,0.01]"), "parts[0].force");
    rejects(&GOOD.replace("[0.5,0.0]", "[1,0.5]"), "parts[0]");
    rejects(&GOOD.replace("[[-1,-0.5],[1,-0.5],[1,0.5],[-1,0.5]]", "[]"), "centers");
    rejects(&GOOD.replace("[0.01,0.01]", "[1e999,0.01]"), "parts[0].force");
    rejects(&GOOD.replace("[0.5,0.0]", "[1e300,1e300]"), "parts[0].position");
    rejects(&GOOD.replace("[0.01,0.01]", "[1e200,0.01]"), "parts[0].force");
    rejects(&GOOD.replace("\"mu_m_g\"", "\"mu_mg\""), "mu_mg");
    rejects("{\"mu_m_g\": 0.1, \"centers\": [[0,0]", "line");
    rejects("", "line");
}

#[test]
fn missing_file_is_one_line() {
    let out = upm(&["solve", "no/such/file.json"], None);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("no/such/file.json"), "{err}");
}

#[test]
fn validate_runs_and_plots() {
    let dir = std::env::temp_dir().join(format!("upm_cli_validate_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let svg = dir.join("field.svg");
    let v = json(&upm(
        &["validate", "examples/paper-3-1.json", "--cycles", "2", "--plot", svg.to_str().expect("utf-8")],
        None,
    ));
    assert_eq!(v["simulated"]["forces"].as_array().expect("forces").len(), 2);
    let text = std::fs::read_to_string(&svg).expect("svg written");
    assert!(text.starts_with("<svg") || text.contains("<svg"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn status_without_a_core_says_so() {
    let prefix = format!("upmt_nocore_{}_", std::process::id());
    let out = upm(&["status", "--prefix", &prefix, "--timeout", "0.3"], None);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("no upm-core is running"), "{err}");
    ipc_types::rig_node::remove_prefix_segment(&prefix);
}

#[test]
fn bad_shapes_and_part_curls_are_one_line_naming_the_field() {
    let with =
        |extra: &str| GOOD.replace("\"force\":[0.01,0.01]}", &format!("\"force\":[0.01,0.01],{extra}}}"));
    json(&upm(&["solve", "-"], Some(&with(r#""shape":{"disc":{"radius":0.02}},"curl":0.001"#))));
    json(&upm(&["solve", "-"], Some(&with(r#""shape":"point""#))));
    // With part_dynamics, a part that grips harder slides less: another answer.
    let sliding = |extra: &str| with(extra).replacen('{', r#"{"part_dynamics":true,"#, 1);
    let (grips, model) = (
        json(&upm(&["solve", "-"], Some(&sliding(r#""friction":1.25"#)))),
        json(&upm(&["solve", "-"], Some(&sliding(r#""friction":1.0"#)))),
    );
    assert_ne!(grips["k"], model["k"], "friction changed nothing");
    assert_eq!(
        model["k"],
        json(&upm(&["solve", "-"], Some(&GOOD.replacen('{', r#"{"part_dynamics":true,"#, 1))))["k"],
        "absent is 1"
    );
    json(&upm(&["solve", "-"], Some(&with(r#""shape":{"polygon":{"vertices":[[0,0],[0.02,0],[0,0.02]]}}"#))));
    for (bad, field) in [
        (r#""shape":{"disc":{"radius":0}}"#, "parts[0].shape"),
        (r#""shape":{"disc":{"radius":-1}}"#, "parts[0].shape"),
        (r#""shape":{"disc":{}}"#, "parts[0].shape"),
        (r#""shape":{"circle":{"radius":0.1}}"#, "parts[0].shape"),
        (r#""shape":"square""#, "parts[0].shape"),
        (r#""shape":{"polygon":{"vertices":[[0,0],[1,0]]}}"#, "parts[0].shape"),
        (r#""shape":{"polygon":{"vertices":[[0,0],[2,0],[1,0.5],[2,2],[0,2]]}}"#, "parts[0].shape"),
        (r#""shape":{"polygon":{"vertices":[[0,0],[1,1],[1,0],[0,1]]}}"#, "parts[0].shape"),
        (r#""shape":{"polygon":{"vertices":[[0,0],[1,0],[2,0]]}}"#, "parts[0].shape"),
        (
            r#""shape":{"polygon":{"vertices":[[0,0],[1,0],[2,1],[2,2],[1,3],[0,3],[-1,2],[-1,1],[-0.5,0.2]]}}"#,
            "parts[0].shape",
        ),
        (r#""curl":"x""#, "parts[0].curl"),
        (r#""curl":null,"shape":{"disc":{"radius":1e999}}"#, "parts[0].shape"),
        (r#""friction":0"#, "parts[0].friction"),
        (r#""friction":-1.2"#, "parts[0].friction"),
        (r#""friction":"x""#, "parts[0].friction"),
        (r#""friction":1e999"#, "parts[0].friction"),
        (r#""friction":3.5"#, "parts[0].friction"),
        (r#""friction":1e-300"#, "parts[0].friction"),
    ] {
        rejects(&with(bad), field);
    }
}

/// A part asked for force and curl together on its disc: `validate` plays
/// it and reports the per-part curl after the top-level ones.
#[test]
fn validate_reports_a_shaped_parts_curl_after_the_top_level_ones() {
    let input = r#"{"mu_m_g": 0.1, "k_max": 0.75,
        "centers": [[-1,-0.5],[-0.3,-0.55],[0.4,-0.55],[1,-0.5],[1.05,0],[1,0.5],[0.3,0.55],[-0.4,0.55],[-1,0.5],[-1.05,0]],
        "curls": [{"position": [-0.5, 0.1], "curl": 0.002}],
        "parts": [{"position": [0.1, 0.05], "force": [0.004, 0.002], "shape": {"disc": {"radius": 0.03}}, "curl": -0.003}]}"#;
    let v = json(&upm(&["validate", "-"], Some(input)));
    let s = &v["simulated"];
    let curls: Vec<f64> = s["curls"].as_array().expect("curls").iter().filter_map(|x| x.as_f64()).collect();
    assert_eq!(curls.len(), 2, "{s}");
    // Signs as asked, in that order.
    assert!(curls[0] > 0.0 && curls[1] < 0.0, "{curls:?}");
    assert_eq!(s["forces"].as_array().map(Vec::len), Some(1));
}
