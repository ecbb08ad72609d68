//! The systems `upm bench solver` times, and one timed solve.

use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rt_core::alloc_count;
use upm_solver::{ForceConstraint, Problem, Solver};

pub const MU_M_G: f64 = 0.1;

/// One benchmark system: parts on the plate, centers around it, and forces
/// `A·k0` with small k0, so the system is consistent and its minimum-norm
/// solution lies inside the bounds (`saturated` = false) for a small `k_scale`.
#[derive(Debug, Clone)]
pub struct BenchCase {
    pub centers: Vec<[f64; 2]>,
    pub parts: Vec<ForceConstraint>,
}

/// Unit-intensity field matrix scaled as the model (Eq. 10): rows x then y.
pub fn field_matrix(centers: &[[f64; 2]], parts: &[ForceConstraint]) -> DMatrix<f64> {
    let (m, n) = (2 * parts.len(), centers.len());
    let mut a = DMatrix::zeros(m, n);
    for (i, p) in parts.iter().enumerate() {
        for (j, &c) in centers.iter().enumerate() {
            let f = upm_solver::field::rotation_force(1.0, MU_M_G, c, p.position);
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
    let mut parts: Vec<ForceConstraint> = pts
        .iter()
        .map(|&position| ForceConstraint {
            position,
            force: Some([0.0; 2]),
            shape: upm_solver::PartShape::Point,
        })
        .collect();
    let a = field_matrix(&centers, &parts);
    let k0 = DVector::from_fn(n, |_, _| rng.random_range(-k_scale..k_scale));
    let f = &a * k0;
    for (i, p) in parts.iter_mut().enumerate() {
        p.force = Some([f[i], f[n_parts + i]]);
    }
    BenchCase { centers, parts }
}

/// One `Solver::solve`, timed (µs); the allocations it made on this thread
/// are added to `allocations`.
pub fn timed_solve(
    solver: &mut Solver,
    p: &Problem<'_>,
    sol: &mut upm_solver::Solution,
    allocations: &mut u64,
) -> (Result<(), upm_solver::SolveError>, f64) {
    let ((r, us), n) = alloc_count::allocations_in(|| {
        let t = Instant::now();
        let r = solver.solve(p, sol);
        (r, t.elapsed().as_secs_f64() * 1e6)
    });
    *allocations += n;
    std::hint::black_box(sol.k());
    (r, us)
}
