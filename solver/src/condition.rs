//! κ₂(A) = κ₂(R) estimated with a fixed number of power iterations on RᵀR
//! (σ_max) and inverse iterations (σ_min), each stopping early once its
//! estimate settles. Bounded work: at most 2·iters triangular
//! products and 2·iters triangular solves of size d, O(d²) each. Each step
//! gives a lower bound, and a factor-of-two estimate is all the exact-path
//! gate (κ ≤ 1e10) and the report need, so the stopping tolerance is loose. A lower
//! bound on the true κ₂ that converges quickly; tests check it against a
//! full SVD.
//!
//! The loops run on R's column-major storage directly: for the d ≤ 64 of a
//! solve, faer's per-call dispatch cost more than the arithmetic.

use multiversion::multiversion;

use super::dense::{axpy, dot, sum_sq};

/// Upper-triangular R, column-major with leading dimension `lead`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct UpperTriangular<'a> {
    pub data: &'a [f64],
    pub lead: usize,
    pub dim: usize,
}

impl UpperTriangular<'_> {
    /// Column j, rows 0..=j.
    #[inline(always)]
    fn col(&self, j: usize) -> &[f64] {
        &self.data[j * self.lead..j * self.lead + j + 1]
    }
}

/// `v`, `w` and `u` are scratch vectors of length ≥ d; `inv_diag` ≥ d too.
/// Each estimate stops once a step changes it by less than `tolerance`
/// (relative), after at most `iters` steps.
/// AVX2 clone where the CPU has it (no fused multiply-adds: bit-identical).
#[multiversion(targets("x86_64+avx2"))]
pub(crate) fn condition_estimate<'r, 's>(
    r: UpperTriangular<'r>,
    iters: usize,
    tolerance: f64,
    scratch: ConditionScratch<'s>,
) -> f64 {
    let d = r.dim;
    if d == 0 {
        return 1.0;
    }
    // At least one step each way (0 iterations would report κ = 0 and pass
    // every gate); a tolerance ≥ 1 would stop after the first step.
    let iters = iters.max(1);
    let tolerance = tolerance.clamp(0.0, 0.5);
    let (v, w, u, inv_diag) =
        (&mut scratch.v[..d], &mut scratch.w[..d], &mut scratch.u[..d], &mut scratch.inv_diag[..d]);
    // Multiplying by reciprocals keeps divisions off the solves' critical path.
    for (j, x) in inv_diag.iter_mut().enumerate() {
        *x = 1.0 / r.col(j)[j];
    }
    // σ_max starts from a fixed vector unlikely to be orthogonal to the top
    // singular vector (R's first row was worse once R is unpivoted). σ_min's
    // first forward solve Rᵀz = e picks each eⱼ = ±1 against the running
    // sum, as LINPACK's xTRCO does, so z grows along R's weakest direction
    // from step one.
    for (j, x) in v.iter_mut().enumerate() {
        *x = 1.0 + 0.1 * (j as f64 * 0.618_033_988_75).fract();
    }
    normalize(v);
    let mut first_inverse_step = true;
    // ‖e‖ = √d: the first inverse step's growth is measured against it.
    let mut start_norm = (d as f64).sqrt();

    // The power step (v, on σ_max) and the inverse step (u, on σ_min) are
    // independent chains; one loop lets the CPU overlap their latencies.
    let (mut sigma_max_sq, mut inv_sigma_min_sq) = (0.0, 0.0);
    let (mut max_done, mut min_done) = (false, false);
    for _ in 0..iters {
        if !max_done {
            // w = R v (column sweep), then v = Rᵀ w (dot with each column).
            w.fill(0.0);
            for j in 0..d {
                axpy(v[j], r.col(j), w);
            }
            for j in 0..d {
                v[j] = dot(r.col(j), w);
            }
            let prev = sigma_max_sq;
            sigma_max_sq = normalize(v);
            max_done = converged(prev, sigma_max_sq, tolerance);
        }
        if !min_done {
            // u ← R⁻ᵀ u (forward), then u ← R⁻¹ u (backward, column sweep).
            for j in 0..d {
                let c = r.col(j);
                let s = dot(&c[..j], u);
                let rhs = if first_inverse_step { -(1f64.copysign(s)) } else { u[j] };
                u[j] = (rhs - s) * inv_diag[j];
            }
            first_inverse_step = false;
            for j in (0..d).rev() {
                let c = r.col(j);
                u[j] *= inv_diag[j];
                let uj = u[j];
                axpy(-uj, &c[..j], &mut u[..j]);
            }
            let prev = inv_sigma_min_sq;
            inv_sigma_min_sq = normalize(u) / start_norm;
            start_norm = 1.0;
            min_done = converged(prev, inv_sigma_min_sq, tolerance);
        }
        if max_done && min_done {
            break;
        }
    }
    let kappa = (sigma_max_sq * inv_sigma_min_sq).sqrt();
    if kappa.is_finite() { kappa } else { f64::INFINITY }
}

/// Scratch vectors of [`condition_estimate`].
pub(crate) struct ConditionScratch<'a> {
    pub v: &'a mut [f64],
    pub w: &'a mut [f64],
    pub u: &'a mut [f64],
    pub inv_diag: &'a mut [f64],
}

/// Power-iteration estimates grow monotonically towards the true value.
fn converged(prev: f64, next: f64, tolerance: f64) -> bool {
    (next - prev).abs() <= tolerance * next.abs()
}

#[inline(always)]
fn normalize(v: &mut [f64]) -> f64 {
    let norm = sum_sq(v).sqrt();
    if norm > 0.0 && norm.is_finite() {
        let inv = 1.0 / norm;
        v.iter_mut().for_each(|x| *x *= inv);
    }
    norm
}
