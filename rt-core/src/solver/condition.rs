//! κ₂(A) = κ₂(R) estimated with a fixed number of power iterations on RᵀR
//! (σ_max) and inverse iterations (σ_min). Bounded work: 2·iters triangular
//! products/solves of size d. A lower bound on the true κ₂ that converges
//! quickly; tests check it against a full SVD.

use faer::linalg::triangular_solve;
use faer::{MatMut, MatRef, Par};

/// `v` and `w` are scratch vectors of length ≥ d.
pub(crate) fn condition_estimate(r: MatRef<'_, f64>, iters: usize, v: &mut [f64], w: &mut [f64]) -> f64 {
    let d = r.nrows();
    if d == 0 {
        return 1.0;
    }
    let (v, w) = (&mut v[..d], &mut w[..d]);
    let start = |v: &mut [f64]| {
        // Deterministic, not orthogonal to the usual singular vectors.
        for (i, x) in v.iter_mut().enumerate() {
            *x = 1.0 + 0.1 * (i as f64 * 0.618_033_988_75).fract();
        }
        normalize(v);
    };

    start(v);
    let mut sigma_max_sq = 0.0;
    for _ in 0..iters {
        // w = R v, v = Rᵀ w
        for i in 0..d {
            w[i] = (i..d).map(|j| r[(i, j)] * v[j]).sum();
        }
        for j in 0..d {
            v[j] = (0..=j).map(|i| r[(i, j)] * w[i]).sum();
        }
        sigma_max_sq = normalize(v);
    }

    start(v);
    let mut inv_sigma_min_sq = 0.0;
    for _ in 0..iters {
        triangular_solve::solve_lower_triangular_in_place(
            r.transpose(),
            MatMut::from_column_major_slice_mut(&mut *v, d, 1),
            Par::Seq,
        );
        triangular_solve::solve_upper_triangular_in_place(
            r,
            MatMut::from_column_major_slice_mut(&mut *v, d, 1),
            Par::Seq,
        );
        inv_sigma_min_sq = normalize(v);
    }
    let kappa = (sigma_max_sq * inv_sigma_min_sq).sqrt();
    if kappa.is_finite() { kappa } else { f64::INFINITY }
}

fn normalize(v: &mut [f64]) -> f64 {
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm > 0.0 && norm.is_finite() {
        v.iter_mut().for_each(|x| *x /= norm);
    }
    norm
}
