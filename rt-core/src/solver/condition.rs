//! κ₂(A) = κ₂(R) estimated with a fixed number of power iterations on RᵀR
//! (σ_max) and inverse iterations (σ_min), each stopping early once its
//! estimate settles. Bounded work: at most 2·iters triangular
//! products and 2·iters triangular solves of size d, O(d²) each. A lower
//! bound on the true κ₂ that converges quickly; tests check it against a
//! full SVD.
//!
//! The loops run on R's column-major storage directly: for the d ≤ 64 of a
//! solve, faer's per-call dispatch cost more than the arithmetic.

/// Upper-triangular R, column-major with leading dimension `lead`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct UpperTriangular<'a> {
    pub data: &'a [f64],
    pub lead: usize,
    pub dim: usize,
}

impl UpperTriangular<'_> {
    /// Column j, rows 0..=j.
    #[inline]
    fn col(&self, j: usize) -> &[f64] {
        &self.data[j * self.lead..j * self.lead + j + 1]
    }
}

/// `v` and `w` are scratch vectors of length ≥ d; `inv_diag` ≥ d too.
pub(crate) fn condition_estimate(
    r: UpperTriangular<'_>,
    iters: usize,
    v: &mut [f64],
    w: &mut [f64],
    inv_diag: &mut [f64],
) -> f64 {
    let d = r.dim;
    if d == 0 {
        return 1.0;
    }
    let (v, w, inv_diag) = (&mut v[..d], &mut w[..d], &mut inv_diag[..d]);
    // Multiplying by reciprocals keeps divisions off the solves' critical path.
    for (j, x) in inv_diag.iter_mut().enumerate() {
        *x = 1.0 / r.col(j)[j];
    }
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
        // w = R v (column sweep), then v = Rᵀ w (dot with each column).
        w.fill(0.0);
        for j in 0..d {
            let vj = v[j];
            for (wi, rij) in w.iter_mut().zip(r.col(j)) {
                *wi += rij * vj;
            }
        }
        for j in 0..d {
            v[j] = r.col(j).iter().zip(w.iter()).map(|(a, b)| a * b).sum();
        }
        let prev = sigma_max_sq;
        sigma_max_sq = normalize(v);
        if converged(prev, sigma_max_sq) {
            break;
        }
    }

    start(v);
    let mut inv_sigma_min_sq = 0.0;
    for _ in 0..iters {
        // v ← R⁻ᵀ v (forward), then v ← R⁻¹ v (backward, column sweep).
        for j in 0..d {
            let c = r.col(j);
            let s: f64 = c[..j].iter().zip(v.iter()).map(|(a, b)| a * b).sum();
            v[j] = (v[j] - s) * inv_diag[j];
        }
        for j in (0..d).rev() {
            let c = r.col(j);
            v[j] *= inv_diag[j];
            let vj = v[j];
            for (vi, rij) in v[..j].iter_mut().zip(&c[..j]) {
                *vi -= rij * vj;
            }
        }
        let prev = inv_sigma_min_sq;
        inv_sigma_min_sq = normalize(v);
        if converged(prev, inv_sigma_min_sq) {
            break;
        }
    }
    let kappa = (sigma_max_sq * inv_sigma_min_sq).sqrt();
    if kappa.is_finite() { kappa } else { f64::INFINITY }
}

/// Power-iteration estimates grow monotonically towards the true value; stop
/// once a step adds less than 1e-6 (relative). At most `iters` steps either way.
fn converged(prev: f64, next: f64) -> bool {
    (next - prev).abs() <= 1e-6 * next.abs()
}

fn normalize(v: &mut [f64]) -> f64 {
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm > 0.0 && norm.is_finite() {
        let inv = 1.0 / norm;
        v.iter_mut().for_each(|x| *x *= inv);
    }
    norm
}
