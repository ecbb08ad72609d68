//! `upm validate` on the paper's examples (§3.1, §3.3) and on random
//! geometries: simulated average force within 5 % of the request
//! (+ 0.01·μmg), simulated curl of the right sign and within 15 %.

use upm_paper::solve_json::{CurlInput, PartInput, ShapeInput, SolveInput, parse};
use upm_paper::{solve_json, validate};

fn paper_31() -> SolveInput {
    parse(
        r#"{ "mu_m_g": 0.1,
             "centers": [[-1,-0.5],[1,-0.5],[1,0.5],[-1,0.5]],
             "parts": [{"position":[0.5,0.0],"force":[0.01,0.01]},
                       {"position":[-0.75,0.25],"force":[-0.01,0.0]}] }"#,
    )
    .expect("valid input")
}

fn paper_33() -> SolveInput {
    parse(
        r#"{ "mu_m_g": 0.1,
             "centers": [[-1,-0.5],[1,-0.5],[1,0.5]],
             "parts": [{"position":[0.5,0.0],"force":[0.0,0.0]}],
             "curls": [{"position":[0.5,0.0],"curl":-0.05}] }"#,
    )
    .expect("valid input")
}

fn check(v: &serde_json::Value) {
    let sim = &v["simulated"];
    for (i, ok) in sim["force_within_target"].as_array().expect("array").iter().enumerate() {
        assert!(
            ok.as_bool() != Some(false),
            "part {i}: {} (error/μmg {})",
            sim["forces"][i],
            sim["force_error_over_mu_m_g"][i]
        );
    }
    for (i, ok) in sim["curl_within_target"].as_array().expect("array").iter().enumerate() {
        assert_eq!(
            ok.as_bool(),
            Some(true),
            "curl {i}: {} (rel. error {})",
            sim["curls"][i],
            sim["curl_relative_error"][i]
        );
    }
}

#[test]
fn paper_force_example_meets_targets() {
    let v = validate::run(&paper_31(), 5, 1, None).expect("validate");
    println!("{}", serde_json::to_string_pretty(&v["simulated"]).unwrap_or_default());
    check(&v);
    // Same k as solve.
    let k: Vec<f64> = serde_json::from_value(v["k"].clone()).expect("k");
    assert!((k[0] - 0.58).abs() < 0.01 && (k[3] + 0.095).abs() < 0.01);
}

#[test]
fn paper_curl_example_meets_targets() {
    let v = validate::run(&paper_33(), 5, 1, None).expect("validate");
    println!("{}", serde_json::to_string_pretty(&v["simulated"]).unwrap_or_default());
    check(&v);
}

#[test]
fn plot_is_written() {
    let path = std::env::temp_dir().join(format!("upm_validate_{}.svg", std::process::id()));
    validate::run(&paper_31(), 1, 1, Some(&path)).expect("validate");
    let svg = std::fs::read_to_string(&path).expect("svg written");
    assert!(svg.contains("<svg") && svg.len() > 10_000);
    let _ = std::fs::remove_file(&path);
}

/// Deterministic pseudo-random numbers for the random geometries.
fn lcg(s: &mut u64) -> f64 {
    *s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*s >> 11) as f64 / (1u64 << 53) as f64
}

/// 4–6 centers around the plate edge, 1–2 parts inside, forces up to
/// 0.12·μmg, sometimes a curl at the first part.
fn random_case(s: &mut u64) -> SolveInput {
    let n = 4 + (lcg(s) * 3.0) as usize;
    let centers = (0..n)
        .map(|j| {
            let a = std::f64::consts::TAU * (j as f64 + 0.3 * lcg(s)) / n as f64;
            [1.1 * a.cos(), 0.6 * a.sin()]
        })
        .collect();
    let m = 1 + (lcg(s) * 2.0) as usize;
    let parts: Vec<PartInput> = (0..m)
        .map(|_| PartInput {
            position: [1.2 * lcg(s) - 0.6, 0.6 * lcg(s) - 0.3],
            force: Some([0.024 * lcg(s) - 0.012, 0.024 * lcg(s) - 0.012]),
            shape: ShapeInput::Point,
            curl: None,
            friction: None,
        })
        .collect();
    let curls = if m == 1 && lcg(s) < 0.5 {
        vec![CurlInput { position: parts[0].position, curl: if lcg(s) < 0.5 { -0.03 } else { 0.03 } }]
    } else {
        vec![]
    };
    SolveInput { mu_m_g: 0.1, centers, parts, curls, k_max: None, part_dynamics: false }
}

#[test]
fn random_geometries_meet_targets() {
    let mut seed = 42u64;
    let (mut tried, mut skipped, mut failed) = (0, 0, Vec::new());
    while tried < 30 {
        let input = random_case(&mut seed);
        let Ok(out) = solve_json::solve(&input) else { continue };
        // Only cases the model says are exactly reachable and playable.
        if out.saturated || out.residual > 1e-9 {
            continue;
        }
        tried += 1;
        match validate::run(&input, 3, tried as u64, None) {
            Err(e) => {
                skipped += 1;
                println!("case {tried}: not playable: {e}");
            }
            Ok(v) => {
                let sim = &v["simulated"];
                let f_ok = sim["force_within_target"]
                    .as_array()
                    .is_some_and(|a| a.iter().all(|x| x.as_bool() != Some(false)));
                let c_ok = sim["curl_within_target"]
                    .as_array()
                    .is_some_and(|a| a.iter().all(|x| x.as_bool() == Some(true)));
                println!(
                    "case {tried}: k {} err/μmg {} curl rel {}",
                    v["k"], sim["force_error_over_mu_m_g"], sim["curl_relative_error"]
                );
                if !(f_ok && c_ok) {
                    failed.push(tried);
                }
            }
        }
    }
    println!("random: {tried} cases, {skipped} not playable, {} failed: {failed:?}", failed.len());
    // Each center is bounded by what it can play: nothing solved is refused.
    assert_eq!(skipped, 0, "unplayable cases: {skipped}");
    assert!(failed.is_empty(), "cases missing the targets: {failed:?}");
}

/// What priority ordering buys: force error (in μmg) with the solver's
/// priority order vs the reverse order, over random geometries. Prints the
/// table in BENCHMARKS.md ("What priority ordering buys"). Run with
/// `cargo test --release -p upm-cli --test validate_paper -- --ignored --nocapture ordering`.
#[test]
#[ignore]
fn ordering_study() {
    let mut seed = 7u64;
    let setup = validate::ValidateSetup::default();
    let (mut e_pri, mut e_rev, mut e_in) = (Vec::new(), Vec::new(), Vec::new());
    let (mut better, mut cases) = (0, 0);
    while cases < 200 {
        let input = random_case(&mut seed);
        let Ok(out) = solve_json::solve(&input) else { continue };
        if out.saturated || out.residual > 1e-9 {
            continue;
        }
        let pri: Vec<u16> = out.order.iter().map(|&j| j as u16).collect();
        let rev: Vec<u16> = pri.iter().rev().copied().collect();
        let inp: Vec<u16> = (0..input.centers.len() as u16).collect();
        let err = |order: &[u16]| -> Option<f64> {
            let m = validate::measure(&input, &out.k, order, 2, 1, &setup, &[]).ok()?;
            let worst = input
                .parts
                .iter()
                .zip(&m.forces)
                .filter_map(|(p, s)| p.force.map(|f| (s[0] - f[0]).hypot(s[1] - f[1]) / input.mu_m_g))
                .fold(0.0, f64::max);
            Some(worst)
        };
        let (Some(a), Some(b), Some(c)) = (err(&pri), err(&rev), err(&inp)) else { continue };
        cases += 1;
        better += (a < b) as usize;
        e_pri.push(a);
        e_rev.push(b);
        e_in.push(c);
    }
    let stats = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        (mean, v[v.len() / 2], v[(v.len() * 95) / 100], v[v.len() - 1])
    };
    println!("| order | mean | median | p95 | max |  (worst-part force error / μmg, {cases} cases)");
    for (name, v) in [("priority", &mut e_pri), ("reverse", &mut e_rev), ("input", &mut e_in)] {
        let (m, med, p95, mx) = stats(v);
        println!(
            "| {name} | {:.3}% | {:.3}% | {:.3}% | {:.3}% |",
            100.0 * m,
            100.0 * med,
            100.0 * p95,
            100.0 * mx
        );
    }
    println!("priority better than reverse in {better}/{cases} cases");
}

/// Issue 25's case: about 22 centers on and just beyond the plate, k_max
/// 0.75, requests from modest to far beyond what a cycle gives. Every
/// solution is playable (each center bounded by what the rig can play
/// about it), and the output names the centers whose bound was lowered.
#[test]
fn every_solution_plays_on_the_rig() {
    let mut s = 2025u64;
    let (mut lowered_cases, mut played) = (0, 0);
    for case in 0..40 {
        let n = 18 + (lcg(&mut s) * 8.0) as usize;
        let centers: Vec<[f64; 2]> =
            (0..n).map(|_| [2.3 * lcg(&mut s) - 1.15, 1.3 * lcg(&mut s) - 0.65]).collect();
        let gain = 0.01 + 0.3 * lcg(&mut s);
        let parts: Vec<PartInput> = (0..1 + (lcg(&mut s) * 4.0) as usize)
            .map(|_| PartInput {
                position: [1.6 * lcg(&mut s) - 0.8, 0.8 * lcg(&mut s) - 0.4],
                force: Some([gain * (2.0 * lcg(&mut s) - 1.0), gain * (2.0 * lcg(&mut s) - 1.0)]),
                shape: ShapeInput::Point,
                curl: None,
                friction: None,
            })
            .collect();
        let input = SolveInput {
            mu_m_g: 0.1,
            centers,
            parts,
            curls: vec![],
            k_max: Some(0.75),
            part_dynamics: false,
        };
        let v = match validate::run(&input, 1, case, None) {
            Ok(v) => v,
            // A part within the solver's minimum distance of a center is
            // refused by name; that is not this test's concern.
            Err(e) if e.to_string().contains("sits on centers") => {
                println!("case {case}: {e}");
                continue;
            }
            Err(e) => panic!("case {case}: {e:#}"),
        };
        let bounds: Vec<f64> =
            v["k_bounds"].as_array().expect("k_bounds").iter().filter_map(|x| x.as_f64()).collect();
        let lowered: Vec<usize> = v["k_lowered"]
            .as_array()
            .expect("k_lowered")
            .iter()
            .filter_map(|x| x.as_u64())
            .map(|j| j as usize)
            .collect();
        assert_eq!(bounds.len(), n);
        assert_eq!(lowered, (0..n).filter(|&j| bounds[j] < 0.75).collect::<Vec<_>>(), "case {case}");
        for (j, (k, u)) in v["k"].as_array().expect("k").iter().zip(&bounds).enumerate() {
            assert!(
                k.as_f64().is_some_and(|k| k.abs() <= u * (1.0 + 1e-12)),
                "case {case}: k[{j}] {k} > {u}"
            );
        }
        lowered_cases += usize::from(!lowered.is_empty());
        played += 1;
    }
    assert!(played >= 30, "only {played} of 40 cases reached the simulator");
    assert!(lowered_cases > 0, "no case needed a lowered bound: the test shows nothing");
}

/// Ten centers, two point parts: the paper's model (parts at rest) loses
/// about a sixth of the force to the velocity parts pick up through the
/// cycle; `part_dynamics` corrects for it (BENCHMARKS.md, issue 25).
#[test]
fn part_dynamics_recover_what_the_velocity_through_the_cycle_costs() {
    let text = r#"{"mu_m_g": 0.1, "k_max": 0.75,
        "centers": [[-1,-0.5],[-0.3,-0.55],[0.4,-0.55],[1,-0.5],[1.05,0],[1,0.5],[0.3,0.55],[-0.4,0.55],[-1,0.5],[-1.05,0]],
        "parts": [{"position": [0.1, 0.05], "force": [0.004, 0.0]}, {"position": [-0.3, -0.1], "force": [0.0, 0.004]}]}"#;
    let worst = |dynamics: bool| {
        let mut input = parse(text).expect("input");
        input.part_dynamics = dynamics;
        let v = validate::run(&input, 2, 1, None).expect("validate");
        assert_eq!(v["predicted_forces"].as_array().map(Vec::len), Some(if dynamics { 2 } else { 0 }));
        let errs =
            v["simulated"]["force_error"].as_array().expect("errors").iter().filter_map(|e| e.as_f64());
        errs.fold(0.0, f64::max) / 0.004
    };
    let (at_rest, corrected) = (worst(false), worst(true));
    println!("worst force error: parts at rest {at_rest:.3}, part dynamics {corrected:.3} of the request");
    assert!(at_rest > 0.08, "the loss this test is about is gone: {at_rest}");
    // Issue 25's target: within 2 % of the request.
    assert!(corrected < 0.02, "{corrected} vs {at_rest}");
}

/// Issue 25's case: a disc asked for force and curl together. At rest the
/// model loses part of both to what the disc picks up through the cycle
/// (velocity and spin); `part_dynamics` predicts it and asks for the rest.
#[test]
fn part_dynamics_recover_force_and_curl_on_a_disc() {
    let text = r#"{"mu_m_g": 0.1, "k_max": 0.75,
        "centers": [[-1,-0.5],[-0.3,-0.55],[0.4,-0.55],[1,-0.5],[1.05,0],[1,0.5],[0.3,0.55],[-0.4,0.55],[-1,0.5],[-1.05,0]],
        "parts": [{"position": [0.1, 0.05], "force": [0.004, 0.002], "shape": {"disc": {"radius": 0.04}}, "curl": -0.004}]}"#;
    let errors = |dynamics: bool| {
        let mut input = parse(text).expect("input");
        input.part_dynamics = dynamics;
        let v = validate::run(&input, 2, 1, None).expect("validate");
        let s = &v["simulated"];
        let force = s["force_error"][0].as_f64().expect("force error") / 0.004f64.hypot(0.002);
        let curl = s["curl_relative_error"][0].as_f64().expect("curl error");
        (force, curl)
    };
    let (at_rest, corrected) = (errors(false), errors(true));
    println!("disc, force and curl: at rest {at_rest:.3?}, part dynamics {corrected:.3?}");
    assert!(at_rest.0 > 0.08 && at_rest.1 > 0.08, "the loss this test is about is gone: {at_rest:?}");
    // Issue 25's targets: force within 2 %, curl within 10 %.
    assert!(corrected.0 < 0.02 && corrected.1 < 0.10, "{corrected:?} vs {at_rest:?}");
}

/// `validate` measures on a simulator stepped finely enough that its answer
/// hardly moves. Its error falls as 1/substeps (measured on this case: 7.5,
/// 3.8, 1.1 and 0.28 % of the request at 1, 4, 16 and 32 against 64), so
/// halving the step changes no force by more than 0.5 % of the request.
#[test]
fn the_measuring_simulator_is_converged() {
    let text = r#"{"mu_m_g": 0.1, "k_max": 0.75, "part_dynamics": true,
        "centers": [[-1,-0.5],[-0.3,-0.55],[0.4,-0.55],[1,-0.5],[1.05,0],[1,0.5],[0.3,0.55],[-0.4,0.55],[-1,0.5],[-1.05,0]],
        "parts": [{"position": [0.1, 0.05], "force": [0.004, 0.002], "shape": {"disc": {"radius": 0.02}}},
                  {"position": [-0.3, -0.1], "force": [0.0, 0.004]}]}"#;
    let input = parse(text).expect("input");
    let out = solve_json::solve(&input).expect("solve");
    let order: Vec<u16> = out.order.iter().map(|&j| j as u16).collect();
    let forces = |substeps: u32| {
        let d = validate::ValidateSetup::default();
        let setup = validate::ValidateSetup { sim: drivers::SimConfig { substeps, ..d.sim }, ..d };
        validate::measure(&input, &out.k, &order, 2, 1, &setup, &[]).expect("measure").forces
    };
    let gap = |a: &[[f64; 2]], b: &[[f64; 2]]| {
        a.iter().zip(b).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]) / 0.004).fold(0.0, f64::max)
    };
    let used = forces(validate::MEASURE_SUBSTEPS);
    let (half, coarse) = (forces(validate::MEASURE_SUBSTEPS / 2), forces(1));
    println!(
        "half the substeps changes {:.4}, one substep {:.4} of the request",
        gap(&half, &used),
        gap(&coarse, &used)
    );
    assert!(gap(&half, &used) < 0.005, "{half:?} vs {used:?}");
    assert!(gap(&coarse, &used) > 0.02, "one substep is as good: the test shows nothing");
}
