//! Unblocked Householder QR, optionally with column pivoting (LAPACK's
//! xGEQP3/xLAQP2 without blocking), on a column-major `rows × cols` matrix,
//! rows ≥ cols.
//!
//! At the sizes a solve sees (≤ 192 × 128) faer's blocked QR spent more
//! time in per-call SIMD dispatch and block set-up than in arithmetic; this
//! loop does the 2·rows·cols² − ⅔·cols³ flops and nothing else. No
//! iteration: the work is fixed by the size. Column norms are downdated as
//! in LAPACK and recomputed when cancellation makes the downdate unsafe.
//!
//! Storage after `factor`: R on and above the diagonal; below it, the
//! Householder vectors vₖ with an implicit leading 1; H_k = I − τₖ vₖ vₖᵀ
//! and A P = H₀ H₁ … H_{d−1} R.

use multiversion::multiversion;

use super::dense::{axpy, dot, dot4, sum_sq};

/// AVX2 clone where the CPU has it (LLVM may merge `wide`'s SSE2 halves into
/// AVX ops there; measured a few percent). The kernels never fuse a
/// multiply-add, so both clones give bit-identical results.
#[multiversion(targets("x86_64+avx2"))]
fn factor_dispatch<'a>(qr: &mut PivotedQr<'a>, norms: &mut [f64], norms_ref: &mut [f64], pivot: bool) {
    qr.factor_body(norms, norms_ref, pivot);
}

/// Apply H = I − τ v vᵀ (v₀ = 1 at row k, the rest `v` below it) to `x`.
#[inline(always)]
fn reflect_one(tau: f64, k: usize, v: &[f64], x: &mut [f64]) {
    let w = tau * (x[k] + dot(v, &x[k + 1..]));
    x[k] -= w;
    axpy(-w, v, &mut x[k + 1..]);
}

/// Apply H = I − τ v vᵀ (v₀ = 1 at row k) to four columns at once: one pass
/// over v feeds four sums, where one column at a time would be a short dot
/// product dominated by its reduction and tail.
#[inline(always)]
fn reflect_four(tau: f64, k: usize, v: &[f64], cols: [&mut [f64]; 4]) {
    let len = v.len();
    let [(h0, t0), (h1, t1), (h2, t2), (h3, t3)] = cols.map(|c| c.split_at_mut(k + 1));
    let (t0, t1, t2, t3) = (&mut t0[..len], &mut t1[..len], &mut t2[..len], &mut t3[..len]);
    let (c0, c1, c2, c3) = (&mut h0[k], &mut h1[k], &mut h2[k], &mut h3[k]);
    let d = dot4(v, [&*t0, &*t1, &*t2, &*t3]);
    let s = [*c0 + d[0], *c1 + d[1], *c2 + d[2], *c3 + d[3]];
    let w = s.map(|x| tau * x);
    *c0 -= w[0];
    *c1 -= w[1];
    *c2 -= w[2];
    *c3 -= w[3];
    axpy(-w[0], v, t0);
    axpy(-w[1], v, t1);
    axpy(-w[2], v, t2);
    axpy(-w[3], v, t3);
}

/// A factored matrix and its reflectors, borrowed from caller buffers.
pub(crate) struct PivotedQr<'a> {
    pub a: &'a mut [f64],
    pub rows: usize,
    pub cols: usize,
    pub tau: &'a mut [f64],
    /// `perm[i]` = the original column now at position i.
    pub perm: &'a mut [usize],
}

impl PivotedQr<'_> {
    /// Factor in place, with column pivoting if `pivot` (rank-revealing) or
    /// without (cheaper; `perm` is then the identity). `norms` and
    /// `norms_ref` are scratch of length ≥ cols.
    pub fn factor(&mut self, norms: &mut [f64], norms_ref: &mut [f64], pivot: bool) {
        factor_dispatch(self, norms, norms_ref, pivot);
    }

    #[inline(always)]
    fn factor_body(&mut self, norms: &mut [f64], norms_ref: &mut [f64], pivot: bool) {
        let (rows, cols) = (self.rows, self.cols);
        debug_assert!(rows >= cols);
        for j in 0..cols {
            self.perm[j] = j;
        }
        if pivot {
            for j in 0..cols {
                let n = sum_sq(self.col(j)).sqrt();
                norms[j] = n;
                norms_ref[j] = n;
            }
        }
        for k in 0..cols {
            if pivot {
                self.pivot(k, norms, norms_ref);
            }
            let tau = self.make_reflector(k);
            self.tau[k] = tau;
            if tau != 0.0 {
                let (left, right) = self.a.split_at_mut((k + 1) * rows);
                let v = &left[k * rows + k + 1..(k + 1) * rows];
                let trail = &mut right[..(cols - k - 1) * rows];
                let mut groups = trail.chunks_exact_mut(4 * rows);
                for group in &mut groups {
                    let (c0, rest) = group.split_at_mut(rows);
                    let (c1, rest) = rest.split_at_mut(rows);
                    let (c2, c3) = rest.split_at_mut(rows);
                    reflect_four(tau, k, v, [c0, c1, c2, c3]);
                }
                for col in groups.into_remainder().chunks_exact_mut(rows) {
                    reflect_one(tau, k, v, col);
                }
            }
            if pivot {
                self.downdate_norms(k, norms, norms_ref);
            }
        }
    }

    /// Swap the first remaining column of largest norm into place k.
    #[inline(always)]
    fn pivot(&mut self, k: usize, norms: &mut [f64], norms_ref: &mut [f64]) {
        let mut p = k;
        for j in k + 1..self.cols {
            if norms[j] > norms[p] {
                p = j;
            }
        }
        if p != k {
            self.swap_cols(k, p);
            self.perm.swap(k, p);
            norms.swap(k, p);
            norms_ref.swap(k, p);
        }
    }

    /// Remaining column norms after step k (LAPACK's xLAQP2 downdate, with a
    /// recompute where cancellation would make it unsafe).
    #[inline(always)]
    fn downdate_norms(&mut self, k: usize, norms: &mut [f64], norms_ref: &mut [f64]) {
        let tol = f64::EPSILON.sqrt();
        let rows = self.rows;
        for j in k + 1..self.cols {
            if norms[j] == 0.0 {
                continue;
            }
            let ratio = self.a[j * rows + k].abs() / norms[j];
            let shrink = (1.0 - ratio * ratio).max(0.0);
            let rel = norms[j] / norms_ref[j];
            if shrink * rel * rel <= tol {
                let n = sum_sq(&self.col(j)[k + 1..]).sqrt();
                norms[j] = n;
                norms_ref[j] = n;
            } else {
                norms[j] *= shrink.sqrt();
            }
        }
    }

    #[inline(always)]
    fn col(&self, j: usize) -> &[f64] {
        &self.a[j * self.rows..(j + 1) * self.rows]
    }

    #[inline(always)]
    fn swap_cols(&mut self, i: usize, j: usize) {
        let rows = self.rows;
        let (lo, hi) = (i.min(j), i.max(j));
        let (left, right) = self.a.split_at_mut(hi * rows);
        left[lo * rows..(lo + 1) * rows].swap_with_slice(&mut right[..rows]);
    }

    /// Reflector zeroing column k below the diagonal; returns τ.
    #[inline(always)]
    fn make_reflector(&mut self, k: usize) -> f64 {
        let rows = self.rows;
        let col = &mut self.a[k * rows + k..(k + 1) * rows];
        let alpha = col[0];
        let tail_sq = sum_sq(&col[1..]);
        if tail_sq == 0.0 {
            return 0.0;
        }
        let beta = -alpha.signum() * (alpha * alpha + tail_sq).sqrt();
        let inv = 1.0 / (alpha - beta);
        col[1..].iter_mut().for_each(|x| *x *= inv);
        col[0] = beta;
        (beta - alpha) / beta
    }

    /// R's diagonal entry i.
    pub fn r_diag(&self, i: usize) -> f64 {
        self.a[i * self.rows + i]
    }

    /// x ← H_k x for k = d−1 … 0, i.e. x ← Q x (x has `rows` entries).
    pub fn apply_q(&self, x: &mut [f64]) {
        for k in (0..self.cols).rev() {
            self.apply_reflector(k, x);
        }
    }

    /// x ← Qᵀ x.
    pub fn apply_qt(&self, x: &mut [f64]) {
        for k in 0..self.cols {
            self.apply_reflector(k, x);
        }
    }

    fn apply_reflector(&self, k: usize, x: &mut [f64]) {
        let tau = self.tau[k];
        if tau != 0.0 {
            reflect_one(tau, k, &self.col(k)[k + 1..], &mut x[..self.rows]);
        }
    }

    /// x ← R⁻¹ x on the leading `cols` entries (back substitution).
    pub fn solve_r(&self, x: &mut [f64]) {
        for j in (0..self.cols).rev() {
            let c = self.col(j);
            x[j] /= c[j];
            let xj = x[j];
            axpy(-xj, &c[..j], &mut x[..j]);
        }
    }

    /// x ← R⁻ᵀ x on the leading `cols` entries (forward substitution).
    pub fn solve_rt(&self, x: &mut [f64]) {
        for j in 0..self.cols {
            let c = self.col(j);
            x[j] = (x[j] - dot(&c[..j], &x[..j])) / c[j];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic 7 × 5 column-major matrix; column 3 = column 0 + column 1.
    fn rank_four() -> Vec<f64> {
        let mut a: Vec<f64> =
            (0..35).map(|i| ((i * 37 % 11) as f64 - 5.0) * 0.3 + (i as f64).sin()).collect();
        for r in 0..7 {
            a[3 * 7 + r] = a[r] + a[7 + r];
        }
        a
    }

    /// Rebuild Q R column by column and compare with the permuted input.
    fn check_reconstruction(pivot: bool) -> Vec<f64> {
        let (rows, cols) = (7, 5);
        let original = rank_four();
        let mut a = original.clone();
        let (mut tau, mut perm, mut n1, mut n2) =
            (vec![0.0; cols], vec![0; cols], vec![0.0; cols], vec![0.0; cols]);
        let mut qr = PivotedQr { a: &mut a, rows, cols, tau: &mut tau, perm: &mut perm };
        qr.factor(&mut n1, &mut n2, pivot);
        for j in 0..cols {
            let mut x = vec![0.0; rows];
            for i in 0..=j {
                x[i] = qr.a[j * rows + i];
            }
            qr.apply_q(&mut x);
            let want = &original[qr.perm[j] * rows..(qr.perm[j] + 1) * rows];
            for (got, want) in x.iter().zip(want) {
                assert!((got - want).abs() < 1e-12, "pivot {pivot}, column {j}: {got} vs {want}");
            }
        }
        (0..cols).map(|i| qr.r_diag(i).abs()).collect()
    }

    #[test]
    fn q_times_r_rebuilds_the_permuted_matrix() {
        check_reconstruction(false);
        check_reconstruction(true);
    }

    #[test]
    fn pivoting_reveals_the_rank_in_the_last_diagonal_entry() {
        let diag = check_reconstruction(true);
        assert!(diag.windows(2).all(|w| w[0] >= w[1]), "pivoted diagonal not decreasing: {diag:?}");
        assert!(diag[4] < 1e-12 * diag[0], "rank loss not revealed: {diag:?}");
        assert!(diag[3] > 1e-3 * diag[0], "rank four, not less: {diag:?}");
    }

    #[test]
    fn qt_undoes_q() {
        let (rows, cols) = (7, 5);
        let mut a = rank_four();
        let (mut tau, mut perm, mut n1, mut n2) =
            (vec![0.0; cols], vec![0; cols], vec![0.0; cols], vec![0.0; cols]);
        let mut qr = PivotedQr { a: &mut a, rows, cols, tau: &mut tau, perm: &mut perm };
        qr.factor(&mut n1, &mut n2, true);
        let x0: Vec<f64> = (0..rows).map(|i| i as f64 - 2.5).collect();
        let mut x = x0.clone();
        qr.apply_q(&mut x);
        qr.apply_qt(&mut x);
        for (a, b) in x.iter().zip(&x0) {
            assert!((a - b).abs() < 1e-13);
        }
    }
}
