//! `upm bench solver`'s outline rows: the same problems solved with every
//! part a point (the paper's rows, the reference), a disc and an octagon
//! (`solver/src/shape.rs`), so the cost the core pays for outlines is measured
//! beside what it paid without them.

use serde_json::{Value, json};
use upm_solver::{PartShape, Problem, Solver, SolverCapacity, SolverParams};

use crate::solver_case::{MU_M_G, bench_case, timed_solve};

/// (parts, centers): `sort`'s size and the solver's capacity.
const SIZES: [(usize, usize); 2] = [(10, 96), (64, 192)];

fn octagon(radius: f64) -> PartShape {
    let v: Vec<[f64; 2]> = (0..8)
        .map(|i| {
            let a = core::f64::consts::TAU * i as f64 / 8.0;
            [radius * a.cos(), radius * a.sin()]
        })
        .collect();
    PartShape::polygon(&v).unwrap_or(PartShape::Point)
}

/// p50 and p99 (µs) of `Solver::solve` on the case with every part `shape`.
fn time_shape(parts: usize, centers: usize, shape: PartShape, budget_s: f64) -> anyhow::Result<(f64, f64)> {
    let mut case = bench_case(2 * parts, centers, 1000, 0.04);
    case.parts.iter_mut().for_each(|p| p.shape = shape);
    let cap = SolverCapacity { parts, curls: 0, centers };
    let mut solver = Solver::new(cap, SolverParams::default());
    solver.warm_up();
    let mut sol = solver.new_solution();
    let problem = Problem {
        mu_m_g: MU_M_G,
        k_max: 0.95,
        centers: &case.centers,
        parts: &case.parts,
        curls: &[],
        k_bounds: &[],
    };
    let (mut us, mut allocations) = (Vec::new(), 0);
    let started = std::time::Instant::now();
    while started.elapsed().as_secs_f64() < budget_s || us.len() < 20 {
        solver.forget_warm_start();
        let (r, t) = timed_solve(&mut solver, &problem, &mut sol, &mut allocations);
        r.map_err(|e| anyhow::anyhow!("solve: {e}"))?;
        us.push(t);
    }
    us.sort_by(f64::total_cmp);
    Ok((upm_stats::percentile_or_nan(&us, 0.5), upm_stats::percentile_or_nan(&us, 0.99)))
}

/// Per size: points, 15 mm discs and 20 mm octagons, interleaved per size.
pub fn run(budget_s: f64) -> anyhow::Result<Value> {
    let mut rows = Vec::new();
    for (parts, centers) in SIZES {
        let (p50, p99) = time_shape(parts, centers, PartShape::Point, budget_s)?;
        let mut row = json!({ "parts": parts, "centers": centers, "point_p50_us": p50, "point_p99_us": p99 });
        for (name, shape) in [("disc", PartShape::Disc { radius: 0.015 }), ("octagon", octagon(0.02))] {
            let (s50, s99) = time_shape(parts, centers, shape, budget_s)?;
            row[format!("{name}_p50_us")] = json!(s50);
            row[format!("{name}_p99_us")] = json!(s99);
            row[format!("{name}_over_point_p50")] = json!(s50 / p50);
        }
        rows.push(row);
    }
    Ok(Value::Array(rows))
}

pub fn to_text(rows: &Value) -> String {
    let mut s = String::from("outline rows (Solver::solve, µs p50 / p99; every part the same shape):\n");
    for r in rows.as_array().into_iter().flatten() {
        let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
        s += &format!(
            "  {:>2} parts, {:>3} centers: points {:.0} / {:.0}, discs {:.0} / {:.0} ({:.1}×), octagons {:.0} / {:.0} ({:.1}×)\n",
            r["parts"],
            r["centers"],
            f("point_p50_us"),
            f("point_p99_us"),
            f("disc_p50_us"),
            f("disc_p99_us"),
            f("disc_over_point_p50"),
            f("octagon_p50_us"),
            f("octagon_p99_us"),
            f("octagon_over_point_p50"),
        );
    }
    s
}
