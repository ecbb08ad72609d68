//! `upm bench solver`: UPM's solver against nalgebra's SVD pseudo-inverse
//! on the same systems, in the same run, batches alternating A B A B.

use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rt_core::runtime::alloc_count;
use rt_core::{ForceConstraint, Problem, Solver, SolverCapacity, SolverParams};
use serde_json::{Value, json};

const MU_M_G: f64 = 0.1;

/// One benchmark system: parts on the plate, centers around it, and forces
/// `A·k0` with small k0, so the system is consistent and its minimum-norm
/// solution lies inside the bounds (`saturated` = false) unless `bounded`.
#[derive(Debug, Clone)]
pub struct BenchCase {
    pub centers: Vec<[f64; 2]>,
    pub parts: Vec<ForceConstraint>,
}

/// Unit-intensity field matrix scaled as the model (Eq. 10): rows x then y.
fn field_matrix(centers: &[[f64; 2]], parts: &[ForceConstraint]) -> DMatrix<f64> {
    let (m, n) = (2 * parts.len(), centers.len());
    let mut a = DMatrix::zeros(m, n);
    for (i, p) in parts.iter().enumerate() {
        for (j, &c) in centers.iter().enumerate() {
            let f = rt_core::solver::field::rotation_force(1.0, MU_M_G, c, p.position);
            a[(i, j)] = f[0] / n as f64;
            a[(parts.len() + i, j)] = f[1] / n as f64;
        }
    }
    a
}

/// `rows` = 2·parts. `k_scale` sets |k0| (≫ k_max makes a bounded case).
pub fn bench_case(rows: usize, n: usize, seed: u64, k_scale: f64) -> BenchCase {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n_parts = rows / 2;
    let min_sep = (0.3 / (n_parts as f64).sqrt()).min(0.15);
    let mut pts: Vec<[f64; 2]> = Vec::new();
    while pts.len() < n_parts {
        let p = [rng.random_range(-0.95..0.95), rng.random_range(-0.45..0.45)];
        if pts.iter().all(|q| (p[0] - q[0]).hypot(p[1] - q[1]) >= min_sep) {
            pts.push(p);
        }
    }
    let mut centers: Vec<[f64; 2]> = Vec::new();
    while centers.len() < n {
        let c = [rng.random_range(-1.5..1.5), rng.random_range(-1.0..1.0)];
        if pts.iter().all(|q| (c[0] - q[0]).hypot(c[1] - q[1]) >= 0.1) {
            centers.push(c);
        }
    }
    let mut parts: Vec<ForceConstraint> =
        pts.iter().map(|&position| ForceConstraint { position, force: Some([0.0; 2]) }).collect();
    let a = field_matrix(&centers, &parts);
    let k0 = DVector::from_fn(n, |_, _| rng.random_range(-k_scale..k_scale));
    let f = &a * k0;
    for (i, p) in parts.iter_mut().enumerate() {
        p.force = Some([f[i], f[n_parts + i]]);
    }
    BenchCase { centers, parts }
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// Time one size; returns the JSON row.
fn bench_size(rows: usize, n: usize, bounded: bool, budget_s: f64) -> anyhow::Result<Value> {
    let cases: Vec<BenchCase> =
        (0..8).map(|s| bench_case(rows, n, 1000 + s, if bounded { 2.0 } else { 0.04 })).collect();
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
        Problem { mu_m_g: MU_M_G, k_max: 0.95, centers: &c.centers, parts: &c.parts, curls: &[] }
    }
    // Accuracy (exact path only) and the method used.
    let mut max_rel = 0.0f64;
    let mut saturated = 0;
    let mut method = String::new();
    let mut max_condition = 0.0f64;
    for (c, (a, b)) in cases.iter().zip(&systems) {
        solver.solve(&problem(c), &mut sol).map_err(|e| anyhow::anyhow!("solve: {e}"))?;
        saturated += usize::from(sol.saturated);
        max_condition = max_condition.max(sol.condition);
        method = format!("{:?}", sol.method);
        if !bounded {
            let k_ref = a.clone().pseudo_inverse(1e-12).map_err(|e| anyhow::anyhow!("{e}"))? * b;
            let diff = sol.k().iter().zip(k_ref.iter()).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
            max_rel = max_rel.max(diff / k_ref.amax().max(1e-300));
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
    let mut time_upm = |p: &Problem<'_>, out: &mut Vec<f64>| -> anyhow::Result<()> {
        alloc_count::mark_rt_thread(true);
        let before = alloc_count::rt_allocations();
        let t = Instant::now();
        let r = solver.solve(p, &mut sol);
        let dt = t.elapsed().as_secs_f64();
        allocations += alloc_count::rt_allocations() - before;
        alloc_count::mark_rt_thread(false);
        r.map_err(|e| anyhow::anyhow!("solve: {e}"))?;
        out.push(dt * 1e6);
        std::hint::black_box(sol.k());
        Ok(())
    };
    let time_nalgebra = |a: &DMatrix<f64>, b: &DVector<f64>, out: &mut Vec<f64>| -> anyhow::Result<()> {
        let t = Instant::now();
        let k = a.clone().pseudo_inverse(1e-12).map_err(|e| anyhow::anyhow!("{e}"))? * b;
        out.push(t.elapsed().as_secs_f64() * 1e6);
        std::hint::black_box(k);
        Ok(())
    };
    let started = Instant::now();
    let mut round = 0usize;
    while started.elapsed().as_secs_f64() < budget_s || round < 2 {
        for (c, (a, b)) in cases.iter().zip(&systems) {
            let p = problem(c);
            for _ in 0..REPEATS {
                time_upm(&p, &mut upm)?;
            }
            for _ in 0..REPEATS {
                time_nalgebra(a, b, &mut nal)?;
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
    let (u50, n50) = (percentile(&upm, 0.5), percentile(&nal, 0.5));
    Ok(json!({
        "m": rows,
        "n": n,
        "path": if bounded { "bounded" } else { "exact" },
        "method": method,
        "saturated_cases": saturated,
        "upm_p50_us": u50,
        "upm_p99_us": percentile(&upm, 0.99),
        "nalgebra_p50_us": n50,
        "nalgebra_p99_us": percentile(&nal, 0.99),
        "speedup_p50": n50 / u50,
        "interleaved_p50_us": { "upm": percentile(&upm_cold, 0.5), "nalgebra": percentile(&nal_cold, 0.5) },
        "interleaved_speedup_p50": percentile(&nal_cold, 0.5) / percentile(&upm_cold, 0.5),
        "allocations": if counted { json!(allocations) } else { Value::Null },
        "samples": upm.len(),
        "max_condition": max_condition,
        "max_rel_diff": if bounded { Value::Null } else { json!(max_rel) },
    }))
}

/// The headline sizes, a scaling curve to capacity, and bounded cases.
pub fn run(quick: bool) -> anyhow::Result<Value> {
    let budget = if quick { 0.05 } else { 0.6 };
    let mut cases = Vec::new();
    for (m, n) in [(4, 9), (20, 24), (64, 96), (8, 16), (32, 48), (48, 72), (96, 144), (128, 192)] {
        cases.push(bench_size(m, n, false, budget)?);
    }
    let mut bounded = Vec::new();
    for (m, n) in [(4, 9), (20, 24), (64, 96)] {
        bounded.push(bench_size(m, n, true, budget)?);
    }
    Ok(json!({
        "timed": "UPM: Solver::solve (validation, assembly, Householder QR (pivoted only when needed), condition estimate, ordering, achieved forces). nalgebra: DMatrix::pseudo_inverse(1e-12) (SVD) times b, plus one matrix clone.",
        "cases": cases,
        "bounded_cases": bounded,
    }))
}

pub fn to_text(v: &Value) -> String {
    let mut s = format!(
        "{:>4} {:>4} {:>8} {:>10} {:>10} {:>12} {:>12} {:>8} {:>12} {:>6} {:>10} {:>9}\n",
        "m",
        "n",
        "path",
        "upm p50",
        "upm p99",
        "nalg p50",
        "nalg p99",
        "speedup",
        "interleaved",
        "alloc",
        "max rel",
        "max κ"
    );
    for c in
        v["cases"].as_array().into_iter().flatten().chain(v["bounded_cases"].as_array().into_iter().flatten())
    {
        s += &format!(
            "{:>4} {:>4} {:>8} {:>10.2} {:>10.2} {:>12.2} {:>12.2} {:>8.1} {:>12.1} {:>6} {:>10.1e} {:>9.1e}\n",
            c["m"].as_u64().unwrap_or(0),
            c["n"].as_u64().unwrap_or(0),
            c["path"].as_str().unwrap_or(""),
            c["upm_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["upm_p99_us"].as_f64().unwrap_or(f64::NAN),
            c["nalgebra_p50_us"].as_f64().unwrap_or(f64::NAN),
            c["nalgebra_p99_us"].as_f64().unwrap_or(f64::NAN),
            c["speedup_p50"].as_f64().unwrap_or(f64::NAN),
            c["interleaved_speedup_p50"].as_f64().unwrap_or(f64::NAN),
            c["allocations"],
            c["max_rel_diff"].as_f64().unwrap_or(f64::NAN),
            c["max_condition"].as_f64().unwrap_or(f64::NAN),
        );
    }
    s + "times in µs; speedup = nalgebra p50 / UPM p50 in warm A B A B batches; \
         interleaved = the same ratio with single calls alternating (both cold)"
}
