//! `upm bench solver`: UPM's solver against nalgebra's SVD pseudo-inverse
//! (unbounded) and Clarabel (bounded) on the same systems, in the same run,
//! batches alternating A B A B.

use std::path::Path;
use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rt_core::alloc_count;
use serde_json::{Value, json};
use upm_solver::{CurlConstraint, ForceConstraint, Problem, Solver, SolverCapacity, SolverParams};

use crate::faer_reference;
use crate::solver_case::{BenchCase, MU_M_G, bench_case, field_matrix, timed_solve};

/// nalgebra's reference: pinv(A)·b by SVD, plus one matrix clone, timed (µs).
fn timed_pinv(a: &DMatrix<f64>, b: &DVector<f64>) -> anyhow::Result<f64> {
    let t = Instant::now();
    let k = a.clone().pseudo_inverse(1e-12).map_err(|e| anyhow::anyhow!("{e}"))? * b;
    let us = t.elapsed().as_secs_f64() * 1e6;
    std::hint::black_box(k);
    Ok(us)
}

/// A nalgebra matrix or vector in faer's layout.
fn faer_mat<C: nalgebra::Dim, S: nalgebra::RawStorage<f64, nalgebra::Dyn, C>>(
    a: &nalgebra::Matrix<f64, nalgebra::Dyn, C, S>,
) -> faer::Mat<f64> {
    faer::Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// Time one size; returns the JSON row.
fn bench_size(rows: usize, n: usize, budget_s: f64) -> anyhow::Result<Value> {
    let cases: Vec<BenchCase> = (0..8).map(|s| bench_case(rows, n, 1000 + s, 0.04)).collect();
    let cap = SolverCapacity { parts: rows / 2, curls: 0, centers: n };
    let mut solver = Solver::new(cap, SolverParams::default());
    solver.warm_up();
    let mut sol = solver.new_solution();
    let systems: Vec<(DMatrix<f64>, DVector<f64>)> = cases
        .iter()
        .map(|c| {
            let a = field_matrix(&c.centers, &c.parts);
            let b = DVector::from_iterator(
                rows,
                c.parts
                    .iter()
                    .map(|p| p.force.map_or(0.0, |f| f[0]))
                    .chain(c.parts.iter().map(|p| p.force.map_or(0.0, |f| f[1]))),
            );
            (a, b)
        })
        .collect();
    fn problem(c: &BenchCase) -> Problem<'_> {
        Problem {
            mu_m_g: MU_M_G,
            k_max: 0.95,
            centers: &c.centers,
            parts: &c.parts,
            curls: &[],
            k_bounds: &[],
        }
    }
    // Accuracy (exact path only) and the method used.
    let mut max_rel = 0.0f64;
    let mut max_rel_faer = 0.0f64;
    let mut saturated = 0;
    let mut method = String::new();
    let mut max_condition = 0.0f64;
    for (c, (a, b)) in cases.iter().zip(&systems) {
        solver.solve(&problem(c), &mut sol).map_err(|e| anyhow::anyhow!("solve: {e}"))?;
        saturated += usize::from(sol.saturated);
        max_condition = max_condition.max(sol.condition);
        method = format!("{:?}", sol.method);
        {
            let k_ref = a.clone().pseudo_inverse(1e-12).map_err(|e| anyhow::anyhow!("{e}"))? * b;
            let diff = sol.k().iter().zip(k_ref.iter()).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
            max_rel = max_rel.max(diff / k_ref.amax().max(1e-300));
            let k_faer = faer_reference::min_norm(faer_mat(a).as_ref(), faer_mat(b).as_ref());
            let diff = (0..n).map(|j| (sol.k()[j] - k_faer[(j, 0)]).abs()).fold(0.0, f64::max);
            max_rel_faer = max_rel_faer.max(diff / k_ref.amax().max(1e-300));
        }
    }
    // A B A B batches until the budget is spent: each case is solved
    // `REPEATS` times by UPM, then `REPEATS` times by nalgebra, every call
    // timed on its own. Within a batch both run with warm caches; alternating
    // single calls instead would time each one right after the other's
    // eviction of caches and branch history (see `interleaved_p50_us`).
    const REPEATS: usize = 8;
    let (mut upm, mut nal) = (Vec::new(), Vec::new());
    let (mut upm_cold, mut nal_cold) = (Vec::new(), Vec::new());
    let counted = alloc_count::counter_installed();
    let mut allocations = 0u64;
    // Repeats of one problem would warm-start a saturated case: every timed
    // solve here starts cold, as the exact path always does.
    let mut time_upm = |p: &Problem<'_>, out: &mut Vec<f64>| -> anyhow::Result<()> {
        solver.forget_warm_start();
        let (r, us) = timed_solve(&mut solver, p, &mut sol, &mut allocations);
        r.map_err(|e| anyhow::anyhow!("solve: {e}"))?;
        out.push(us);
        Ok(())
    };
    let time_nalgebra = |a: &DMatrix<f64>, b: &DVector<f64>, out: &mut Vec<f64>| -> anyhow::Result<()> {
        out.push(timed_pinv(a, b)?);
        Ok(())
    };
    // faer's inputs in its own layout, made outside the timing.
    let faer_systems: Vec<(faer::Mat<f64>, faer::Mat<f64>, Vec<f64>)> =
        systems.iter().map(|(a, b)| (faer_mat(a), faer_mat(b), b.iter().copied().collect())).collect();
    let mut in_place = faer_reference::MinNormInPlace::new(rows, n);
    let (mut faer_qr, mut faer_in_place, mut faer_allocations) = (Vec::new(), Vec::new(), 0u64);
    let started = Instant::now();
    let mut round = 0usize;
    while started.elapsed().as_secs_f64() < budget_s || round < 2 {
        for ((c, (a, b)), (fa, fb, bs)) in cases.iter().zip(&systems).zip(&faer_systems) {
            let p = problem(c);
            for _ in 0..REPEATS {
                time_upm(&p, &mut upm)?;
            }
            for _ in 0..REPEATS {
                time_nalgebra(a, b, &mut nal)?;
            }
            for _ in 0..REPEATS {
                let t = Instant::now();
                std::hint::black_box(faer_reference::min_norm(fa.as_ref(), fb.as_ref()));
                faer_qr.push(t.elapsed().as_secs_f64() * 1e6);
            }
            for _ in 0..REPEATS {
                let (us, allocs) = alloc_count::allocations_in(|| {
                    let t = Instant::now();
                    std::hint::black_box(in_place.solve(fa.as_ref(), bs));
                    t.elapsed().as_secs_f64() * 1e6
                });
                faer_allocations += allocs;
                faer_in_place.push(us);
            }
            time_upm(&p, &mut upm_cold)?;
            time_nalgebra(a, b, &mut nal_cold)?;
        }
        round += 1;
    }
    upm_cold.sort_by(f64::total_cmp);
    nal_cold.sort_by(f64::total_cmp);
    upm.sort_by(f64::total_cmp);
    nal.sort_by(f64::total_cmp);
    faer_qr.sort_by(f64::total_cmp);
    faer_in_place.sort_by(f64::total_cmp);
    let (u50, n50) = (upm_stats::percentile_or_nan(&upm, 0.5), upm_stats::percentile_or_nan(&nal, 0.5));
    let (fq50, fi50) =
        (upm_stats::percentile_or_nan(&faer_qr, 0.5), upm_stats::percentile_or_nan(&faer_in_place, 0.5));
    Ok(json!({
        "m": rows,
        "n": n,
        "path": "exact",
        "method": method,
        "saturated_cases": saturated,
        "upm_p50_us": u50,
        "upm_p99_us": upm_stats::percentile_or_nan(&upm, 0.99),
        "nalgebra_p50_us": n50,
        "nalgebra_p99_us": upm_stats::percentile_or_nan(&nal, 0.99),
        "speedup_p50": n50 / u50,
        // faer: the same minimum-norm K from a QR of Aᵀ, by `Mat::qr()`
        // (allocating) and by `qr_in_place` on a workspace sized once.
        "faer_qr_p50_us": fq50,
        "faer_qr_p99_us": upm_stats::percentile_or_nan(&faer_qr, 0.99),
        "faer_qr_in_place_p50_us": fi50,
        "faer_qr_in_place_p99_us": upm_stats::percentile_or_nan(&faer_in_place, 0.99),
        "speedup_vs_faer_qr_p50": fq50 / u50,
        "speedup_vs_faer_in_place_p50": fi50 / u50,
        "faer_in_place_allocations": if counted { json!(faer_allocations) } else { Value::Null },
        "faer_max_rel_diff": max_rel_faer,
        "interleaved_p50_us": { "upm": upm_stats::percentile_or_nan(&upm_cold, 0.5), "nalgebra": upm_stats::percentile_or_nan(&nal_cold, 0.5) },
        "interleaved_speedup_p50": upm_stats::percentile_or_nan(&nal_cold, 0.5) / upm_stats::percentile_or_nan(&upm_cold, 0.5),
        "allocations": if counted { json!(allocations) } else { Value::Null },
        "samples": upm.len(),
        "max_condition": max_condition,
        "max_rel_diff": max_rel,
    }))
}

/// A bounded benchmark problem, owned.
#[derive(Debug, Clone)]
pub struct BoundedCase {
    pub name: String,
    pub mu_m_g: f64,
    pub k_max: f64,
    pub centers: Vec<[f64; 2]>,
    pub parts: Vec<ForceConstraint>,
    pub curls: Vec<CurlConstraint>,
}

impl BoundedCase {
    fn problem(&self) -> Problem<'_> {
        Problem {
            mu_m_g: self.mu_m_g,
            k_max: self.k_max,
            centers: &self.centers,
            parts: &self.parts,
            curls: &self.curls,
            k_bounds: &[],
        }
    }
}

/// Consecutive camera frames: every part moved by 1 mm in a random
/// direction from the frame before.
fn frames(case: &BoundedCase, count: usize, seed: u64) -> Vec<Vec<ForceConstraint>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut parts = case.parts.clone();
    (0..count)
        .map(|_| {
            for p in &mut parts {
                let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                p.position[0] += 0.001 * a.cos();
                p.position[1] += 0.001 * a.sin();
            }
            parts.clone()
        })
        .collect()
}

/// Cold, warm, Clarabel and nalgebra on one bounded problem.
fn bench_bounded(case: &BoundedCase, budget_s: f64) -> anyhow::Result<Value> {
    let cap = SolverCapacity {
        parts: case.parts.len().max(1),
        curls: case.curls.len(),
        centers: case.centers.len().max(1),
    };
    let mut solver = Solver::new(cap, SolverParams::default());
    solver.warm_up();
    let mut sol = solver.new_solution();
    solver.solve(&case.problem(), &mut sol).map_err(|e| anyhow::anyhow!("{}: solve: {e}", case.name))?;
    let (k_upm, saturated, iterations_cold) = (sol.k().to_vec(), sol.saturated, sol.iterations);
    let sys = solver.last_system();
    let (rows, b, m, n, eps) = (sys.rows.to_vec(), sys.b.to_vec(), sys.m, sys.n, sys.eps);
    let sys = upm_solver::LeastSquaresSystem { rows: &rows, b: &b, m, n, eps };
    let objective = sys.objective(&k_upm);
    let qp = crate::bounded_reference::BoxQp::new(&sys, case.k_max);
    let k_ref = qp.solve();
    let reference_objective = k_ref.as_ref().map(|k| sys.objective(k));
    let a = DMatrix::from_row_slice(m, n, &rows);
    let bv = DVector::from_column_slice(&b);
    let walk = frames(case, 32, 7);

    let counted = alloc_count::counter_installed();
    let mut allocations = 0u64;
    let (mut cold, mut warm, mut nal, mut clar) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut warm_started, mut warm_iterations) = (0usize, Vec::new());
    // A frame whose solve fails is counted, not timed.
    let mut failed = 0usize;
    let mut time_upm =
        |solver: &mut Solver, p: &Problem<'_>, sol: &mut upm_solver::Solution| -> Option<f64> {
            let (r, us) = timed_solve(solver, p, sol, &mut allocations);
            failed += usize::from(r.is_err());
            r.ok().map(|_| us)
        };
    const REPEATS: usize = 8;
    let started = Instant::now();
    let mut round = 0usize;
    while started.elapsed().as_secs_f64() < budget_s || round < 2 {
        // Cold: the same frames as warm, each with the warm start forgotten.
        for parts in &walk {
            solver.forget_warm_start();
            let p = Problem { parts, ..case.problem() };
            cold.extend(time_upm(&mut solver, &p, &mut sol));
        }
        // Warm: from the base frame, each frame after the one before.
        solver.solve(&case.problem(), &mut sol).map_err(|e| anyhow::anyhow!("{}: solve: {e}", case.name))?;
        for parts in &walk {
            let p = Problem { parts, ..case.problem() };
            if let Some(dt) = time_upm(&mut solver, &p, &mut sol) {
                warm.push(dt);
                warm_started += usize::from(sol.warm_started);
                warm_iterations.push(sol.iterations as f64);
            }
        }
        for _ in 0..REPEATS {
            nal.push(timed_pinv(&a, &bv)?);
        }
        let t = Instant::now();
        std::hint::black_box(qp.solve());
        clar.push(t.elapsed().as_secs_f64() * 1e6);
        round += 1;
    }
    for v in [&mut cold, &mut warm, &mut nal, &mut clar, &mut warm_iterations] {
        v.sort_by(f64::total_cmp);
    }
    let (c50, w50, n50) = (
        upm_stats::percentile_or_nan(&cold, 0.5),
        upm_stats::percentile_or_nan(&warm, 0.5),
        upm_stats::percentile_or_nan(&nal, 0.5),
    );
    Ok(json!({
        "name": case.name,
        "m": m,
        "n": n,
        "saturated": saturated,
        "active": k_upm.iter().filter(|k| k.abs() >= case.k_max * (1.0 - 1e-9)).count(),
        "iterations_cold": iterations_cold,
        "iterations_warm_p50": upm_stats::percentile_or_nan(&warm_iterations, 0.5),
        "upm_cold_p50_us": c50,
        "upm_cold_p99_us": upm_stats::percentile_or_nan(&cold, 0.99),
        "upm_warm_p50_us": w50,
        "upm_warm_p99_us": upm_stats::percentile_or_nan(&warm, 0.99),
        "warm_started_fraction": warm_started as f64 / warm.len().max(1) as f64,
        "reference_p50_us": upm_stats::percentile_or_nan(&clar, 0.5),
        "nalgebra_p50_us": n50,
        "cold_over_nalgebra": c50 / n50,
        "warm_over_nalgebra": w50 / n50,
        "objective": objective,
        "reference_objective": reference_objective,
        "objective_rel_diff": reference_objective.map(|r| (objective - r) / r.abs().max(f64::MIN_POSITIVE)),
        "allocations": if counted { json!(allocations) } else { Value::Null },
        "samples": { "cold": cold.len(), "warm": warm.len(), "reference": clar.len() },
        "failed_solves": failed,
    }))
}

/// The built-in bounded problems: each headline size heavily saturated
/// (random k0 in ±2, k_max 0.95) and moderately (k0 in ±0.6).
fn builtin_bounded() -> Vec<BoundedCase> {
    let mut out = Vec::new();
    for (rows, n) in [(4, 9), (20, 24), (64, 96), (128, 192)] {
        for (label, scale) in [("heavy", 2.0), ("moderate", 0.6)] {
            let c = bench_case(rows, n, 1000, scale);
            out.push(BoundedCase {
                name: format!("{rows}x{n} {label}"),
                mu_m_g: MU_M_G,
                k_max: 0.95,
                centers: c.centers,
                parts: c.parts,
                curls: Vec::new(),
            });
        }
    }
    out
}

/// `--problems FILE`: one `upm solve` input per line. A malformed line is
/// reported on stderr with its number and skipped; the count comes back.
pub fn load_problems(path: &Path) -> anyhow::Result<(Vec<BoundedCase>, usize)> {
    let text = upm_commands::input::read_input(path)?;
    let (mut cases, mut bad) = (Vec::new(), 0);
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let parsed = upm_paper::solve_json::parse(line)
            .and_then(|input| Ok((input.force_constraints()?, input.curl_constraints()?, input)));
        match parsed {
            Ok((parts, curls, input)) => cases.push(BoundedCase {
                name: format!("line {}", i + 1),
                mu_m_g: input.mu_m_g,
                k_max: input.k_max(),
                parts,
                curls,
                centers: input.centers,
            }),
            Err(e) => {
                eprintln!("upm bench solver: {}: line {}: {e}", path.display(), i + 1);
                bad += 1;
            }
        }
    }
    Ok((cases, bad))
}

/// Every problem of a `--problems` file; returns the rows and how many
/// lines were malformed or failed to solve.
pub fn run_problems(path: &Path, quick: bool) -> anyhow::Result<(Value, usize)> {
    let (cases, mut bad) = load_problems(path)?;
    let budget = if quick { 0.05 } else { 0.6 };
    let mut rows = Vec::new();
    for c in &cases {
        match bench_bounded(c, budget) {
            Ok(v) => rows.push(v),
            Err(e) => {
                eprintln!("upm bench solver: {}: {e:#}", path.display());
                bad += 1;
            }
        }
    }
    Ok((Value::Array(rows), bad))
}

/// The headline sizes and a scaling curve to capacity on the exact path,
/// then the bounded problems.
pub fn run(quick: bool) -> anyhow::Result<Value> {
    let budget = if quick { 0.05 } else { 0.6 };
    let mut cases = Vec::new();
    for (m, n) in [(4, 9), (20, 24), (64, 96), (8, 16), (32, 48), (48, 72), (96, 144), (128, 192)] {
        cases.push(bench_size(m, n, budget)?);
    }
    let bounded =
        builtin_bounded().iter().map(|c| bench_bounded(c, budget)).collect::<anyhow::Result<Vec<_>>>()?;
    Ok(json!({
        "timed": "UPM: Solver::solve (validation, assembly, Householder QR (pivoted only when needed), condition estimate, bounded path, ordering, achieved forces); cold and warm time the same 32 consecutive frames (every part moved 1 mm from the frame before): cold with the warm start forgotten before each solve, warm in sequence. objective, saturated and active are those of the base frame. nalgebra: DMatrix::pseudo_inverse(1e-12) (SVD) times b, plus one matrix clone. Clarabel (reference): set-up and solve of the same box-constrained QP (tolerances 1e-12), AᵀA formed outside the timing.",
        "cases": cases,
        "bounded_cases": bounded,
        "outline_rows": crate::bench_solver_shapes::run(budget)?,
    }))
}

pub fn to_text(v: &Value) -> String {
    let mut s = format!(
        "{:>4} {:>4} {:>10} {:>10} {:>12} {:>12} {:>8} {:>10} {:>10} {:>9} {:>12} {:>6} {:>10} {:>9}\n",
        "m",
        "n",
        "upm p50",
        "upm p99",
        "nalg p50",
        "nalg p99",
        "speedup",
        "faer qr",
        "faer inpl",
        "vs inpl",
        "interleaved",
        "alloc",
        "max rel",
        "max κ"
    );
    for c in v["cases"].as_array().into_iter().flatten() {
        s += &format!(
            "{:>4} {:>4} {:>10.2} {:>10.2} {:>12.2} {:>12.2} {:>8.1} {:>10.2} {:>10.2} {:>9.2} {:>12.1} {:>6} {:>10.1e} {:>9.1e}\n",
            c["m"].as_u64().unwrap_or(0),
            c["n"].as_u64().unwrap_or(0),
            c["upm_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["upm_p99_us"].as_f64().unwrap_or(f64::NAN),
            c["nalgebra_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["nalgebra_p99_us"].as_f64().unwrap_or(f64::NAN),
            c["speedup_p50"].as_f64().unwrap_or(f64::NAN),
            c["faer_qr_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["faer_qr_in_place_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["speedup_vs_faer_in_place_p50"].as_f64().unwrap_or(f64::NAN),
            c["interleaved_speedup_p50"].as_f64().unwrap_or(f64::NAN),
            c["allocations"],
            c["max_rel_diff"].as_f64().unwrap_or(f64::NAN),
            c["max_condition"].as_f64().unwrap_or(f64::NAN),
        );
    }
    if !s.is_empty() && v["cases"].is_array() {
        s += "exact path: times in µs; speedup = nalgebra p50 / UPM p50 in warm A B A B batches; faer qr = \
              faer's Mat::qr() min-norm (allocating), faer inpl = faer's qr_in_place on a workspace sized once, \
              vs inpl = its p50 / UPM p50; interleaved = nalgebra / UPM with single calls alternating (both cold)\n\n";
    }
    s += &bounded_text(v.get("bounded_cases").unwrap_or(v));
    if v["outline_rows"].is_array() {
        s += "\n\n";
        s += &crate::bench_solver_shapes::to_text(&v["outline_rows"]);
    }
    s
}

/// The bounded rows (the built-in ones, or a `--problems` array).
pub fn bounded_text(rows: &Value) -> String {
    let mut s = format!(
        "{:<18} {:>4} {:>4} {:>6} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9} {:>9} {:>9} {:>10} {:>6}\n",
        "problem",
        "m",
        "n",
        "active",
        "cold p50",
        "cold p99",
        "warm p50",
        "warm p99",
        "clarabel",
        "nalg p50",
        "cold/nalg",
        "warm/nalg",
        "obj − ref",
        "alloc"
    );
    for c in rows.as_array().into_iter().flatten() {
        s += &format!(
            "{:<18} {:>4} {:>4} {:>6} {:>9.1} {:>9.1} {:>9.1} {:>9.1} {:>10.1} {:>9.1} {:>9.2} {:>9.2} {:>10.1e} {:>6}\n",
            c["name"].as_str().unwrap_or(""),
            c["m"].as_u64().unwrap_or(0),
            c["n"].as_u64().unwrap_or(0),
            c["active"].as_u64().unwrap_or(0),
            c["upm_cold_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["upm_cold_p99_us"].as_f64().unwrap_or(f64::NAN),
            c["upm_warm_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["upm_warm_p99_us"].as_f64().unwrap_or(f64::NAN),
            c["reference_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["nalgebra_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["cold_over_nalgebra"].as_f64().unwrap_or(f64::NAN),
            c["warm_over_nalgebra"].as_f64().unwrap_or(f64::NAN),
            c["objective_rel_diff"].as_f64().unwrap_or(f64::NAN),
            c["allocations"],
        );
    }
    s + "bounded path: times in µs over the same 32 consecutive frames (every part 1 mm on): cold = warm start \
         forgotten, warm = in sequence; active, obj − ref: the base frame; \
         clarabel = the same box-constrained QP by Clarabel (set-up + solve); obj − ref = (UPM − Clarabel) / Clarabel"
}
