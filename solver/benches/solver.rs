//! Criterion view of the solver against nalgebra's SVD pseudo-inverse on
//! the same systems (`cargo bench -p rt-core --bench solver`). The A/B
//! table with allocations and accuracy is `upm bench solver`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use upm_solver::field::rotation_force;
use upm_solver::{ForceConstraint, Problem, Solver, SolverCapacity, SolverParams};

const MU_M_G: f64 = 0.1;

/// Spread parts, centers around the plate, consistent forces A·k₀.
fn case(rows: usize, n: usize) -> (Vec<[f64; 2]>, Vec<ForceConstraint>, DMatrix<f64>, DVector<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let parts_n = rows / 2;
    let mut pts: Vec<[f64; 2]> = Vec::new();
    while pts.len() < parts_n {
        let p = [rng.random_range(-0.95..0.95), rng.random_range(-0.45..0.45)];
        if pts.iter().all(|q| (p[0] - q[0]).hypot(p[1] - q[1]) > 0.08) {
            pts.push(p);
        }
    }
    let mut centers: Vec<[f64; 2]> = Vec::new();
    while centers.len() < n {
        let c = [rng.random_range(-1.5..1.5), rng.random_range(-1.0..1.0)];
        if pts.iter().all(|q| (c[0] - q[0]).hypot(c[1] - q[1]) > 0.1) {
            centers.push(c);
        }
    }
    let mut a = DMatrix::zeros(rows, n);
    for (i, &p) in pts.iter().enumerate() {
        for (j, &c) in centers.iter().enumerate() {
            let f = rotation_force(1.0, MU_M_G, c, p);
            a[(i, j)] = f[0] / n as f64;
            a[(parts_n + i, j)] = f[1] / n as f64;
        }
    }
    let k0 = DVector::from_fn(n, |_, _| rng.random_range(-0.04..0.04));
    let b = &a * k0;
    let parts = pts
        .iter()
        .enumerate()
        .map(|(i, &position)| ForceConstraint {
            position,
            force: Some([b[i], b[parts_n + i]]),
            shape: upm_solver::PartShape::Point,
        })
        .collect();
    (centers, parts, a, b)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("solve");
    for (rows, n) in [(4, 9), (20, 24), (64, 96)] {
        let (centers, parts, a, b) = case(rows, n);
        let mut solver =
            Solver::new(SolverCapacity { parts: rows / 2, curls: 0, centers: n }, SolverParams::default());
        solver.warm_up();
        let mut out = solver.new_solution();
        let problem = Problem {
            mu_m_g: MU_M_G,
            k_max: 0.95,
            centers: &centers,
            parts: &parts,
            curls: &[],
            k_bounds: &[],
        };
        let id = format!("{rows}x{n}");
        g.bench_function(BenchmarkId::new("upm", &id), |bch| {
            bch.iter(|| solver.solve(std::hint::black_box(&problem), &mut out).is_ok())
        });
        g.bench_function(BenchmarkId::new("nalgebra_pinv", &id), |bch| {
            bch.iter(|| a.clone().pseudo_inverse(1e-12).map(|p| p * &b).is_ok())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
