//! The triangular factor of the free block, kept up to date as variables
//! change side instead of refactored.
//!
//! R (|F| × |F|) with RᵀR = A_FᵀA_F + εI, the R of the QR of
//! [A_F; √ε·I]. Freeing variable j appends a column (bordering: Rᵀs =
//! A_Fᵀa_j, ρ² = ‖a_j‖² + ε − ‖s‖², m·|F| + |F|² flops); fixing one deletes
//! its column and restores the triangle with Givens rotations (≤ 3|F|²).
//! Solves use the corrected semi-normal equations (Björck): the normal
//! equations through R, then one refinement step on the true residual,
//! whose error is ~ (κ(M)²u)² rather than κ(M)²u. That is accurate enough
//! to choose steps; the bounded solver confirms its answer with a fresh
//! Householder QR, so the answer never rests on this factor.

use super::dense::{axpy, dot};

#[derive(Debug)]
pub(crate) struct FreeCholesky {
    /// Column-major, leading dimension `ld`; column c holds rows 0..=c.
    r: Vec<f64>,
    ld: usize,
    /// The variable at each position of R.
    order: Vec<usize>,
    len: usize,
    /// False when R does not describe the current free set (after a start,
    /// a bordering step that lost its pivot, or |F| ≥ m): refactor.
    pub valid: bool,
    t: Vec<f64>,
    x: Vec<f64>,
    s: Vec<f64>,
}

impl FreeCholesky {
    pub fn new(max_m: usize, max_n: usize) -> Self {
        let n = max_n.max(1);
        Self {
            r: vec![0.0; n * n],
            ld: n,
            order: vec![0; n],
            len: 0,
            valid: false,
            t: vec![0.0; n],
            x: vec![0.0; n],
            s: vec![0.0; max_m.max(1)],
        }
    }

    /// Take R from a fresh QR: its upper triangle, `lead` rows per column,
    /// for the free variables `free` in that order.
    pub fn load(&mut self, factor: &[f64], lead: usize, free: &[usize]) {
        let nf = free.len();
        for c in 0..nf {
            self.r[c * self.ld..c * self.ld + c + 1].copy_from_slice(&factor[c * lead..c * lead + c + 1]);
        }
        self.order[..nf].copy_from_slice(free);
        self.len = nf;
        self.valid = true;
    }

    /// Free variable j (column a_j of A): append its column. Leaves the
    /// factor invalid if the new pivot has lost its digits.
    pub fn add(&mut self, j: usize, cols: &[f64], m: usize, eps: f64) {
        let nf = self.len;
        let a = &cols[j * m..(j + 1) * m];
        // t = A_Fᵀ a_j, then Rᵀ s = t in place (column c of R is contiguous).
        for c in 0..nf {
            let f = self.order[c];
            self.t[c] = dot(&cols[f * m..(f + 1) * m], a);
        }
        solve_rt(&self.r, self.ld, nf, &mut self.t);
        let d = dot(a, a) + eps;
        let rho2 = d - dot(&self.t[..nf], &self.t[..nf]);
        // ρ² ≥ ε in exact arithmetic; below that the cancellation has eaten
        // it (or ε is negligible against ‖a_j‖²): refactor instead.
        if !(rho2 >= 0.5 * eps && rho2 > 1e-14 * d) {
            self.valid = false;
            return;
        }
        let col = &mut self.r[nf * self.ld..nf * self.ld + nf + 1];
        col[..nf].copy_from_slice(&self.t[..nf]);
        col[nf] = rho2.sqrt();
        self.order[nf] = j;
        self.len = nf + 1;
    }

    /// Fix variable j: delete its column, then rotate the triangle back.
    pub fn remove(&mut self, j: usize) {
        let nf = self.len;
        let Some(p) = self.order[..nf].iter().position(|&v| v == j) else {
            self.valid = false;
            return;
        };
        let ld = self.ld;
        for c in p..nf - 1 {
            self.order[c] = self.order[c + 1];
            self.r.copy_within((c + 1) * ld..(c + 1) * ld + c + 2, c * ld);
        }
        // Column c now has one entry below its diagonal, at row c + 1.
        for c in p..nf - 1 {
            let (a, b) = (self.r[c * ld + c], self.r[c * ld + c + 1]);
            let h = a.hypot(b);
            if h == 0.0 {
                self.valid = false;
                return;
            }
            let (cs, sn) = (a / h, b / h);
            self.r[c * ld + c] = h;
            self.r[c * ld + c + 1] = 0.0;
            for k in c + 1..nf - 1 {
                let (top, bottom) = (self.r[k * ld + c], self.r[k * ld + c + 1]);
                self.r[k * ld + c] = cs * top + sn * bottom;
                self.r[k * ld + c + 1] = cs * bottom - sn * top;
            }
        }
        self.len = nf - 1;
    }

    /// z_F ← argmin ‖A_F z − r‖² + ε‖z‖² (only the free entries of z).
    pub fn solve(&mut self, cols: &[f64], m: usize, eps: f64, rhs: &[f64], z: &mut [f64]) {
        let nf = self.len;
        for c in 0..nf {
            let f = self.order[c];
            self.x[c] = dot(&cols[f * m..(f + 1) * m], rhs);
        }
        normal_solve(&self.r, self.ld, nf, &mut self.x);
        // One refinement step: s = r − A_F x, δ = (RᵀR)⁻¹(A_Fᵀs − εx).
        let s = &mut self.s[..m];
        s.copy_from_slice(rhs);
        for c in 0..nf {
            let f = self.order[c];
            axpy(-self.x[c], &cols[f * m..(f + 1) * m], s);
        }
        for c in 0..nf {
            let f = self.order[c];
            self.t[c] = dot(&cols[f * m..(f + 1) * m], s) - eps * self.x[c];
        }
        normal_solve(&self.r, self.ld, nf, &mut self.t);
        for c in 0..nf {
            z[self.order[c]] = self.x[c] + self.t[c];
        }
    }
}

/// x ← R⁻ᵀ x on the leading `nf` entries (R column-major, leading dimension
/// `ld`, column c holding rows 0..=c): forward substitution.
fn solve_rt(r: &[f64], ld: usize, nf: usize, x: &mut [f64]) {
    for c in 0..nf {
        let col = &r[c * ld..c * ld + c + 1];
        x[c] = (x[c] - dot(&col[..c], &x[..c])) / col[c];
    }
}

/// x ← (RᵀR)⁻¹ x on the leading `nf` entries.
fn normal_solve(r: &[f64], ld: usize, nf: usize, x: &mut [f64]) {
    solve_rt(r, ld, nf, x);
    for c in (0..nf).rev() {
        let col = &r[c * ld..c * ld + c + 1];
        x[c] /= col[c];
        let xc = x[c];
        axpy(-xc, &col[..c], &mut x[..c]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RᵀR against A_FᵀA_F + εI for the current order.
    fn check(ch: &FreeCholesky, cols: &[f64], m: usize, eps: f64) {
        let (nf, ld) = (ch.len, ch.ld);
        for a in 0..nf {
            for b in 0..nf {
                let rr: f64 = (0..=a.min(b)).map(|k| ch.r[a * ld + k] * ch.r[b * ld + k]).sum();
                let (fa, fb) = (ch.order[a], ch.order[b]);
                let g = dot(&cols[fa * m..(fa + 1) * m], &cols[fb * m..(fb + 1) * m])
                    + if a == b { eps } else { 0.0 };
                assert!((rr - g).abs() < 1e-10 * (1.0 + g.abs()), "({a},{b}): {rr} vs {g}");
            }
        }
    }

    #[test]
    fn adding_and_removing_columns_keeps_the_gram_matrix() {
        let (m, n, eps) = (6, 5, 1e-3);
        let cols: Vec<f64> =
            (0..m * n).map(|i| ((i * 37 % 11) as f64 - 5.0) * 0.3 + (i as f64).sin()).collect();
        let mut ch = FreeCholesky::new(m, n);
        ch.load(&[], 1, &[]);
        for j in [3, 0, 4, 1] {
            ch.add(j, &cols, m, eps);
            assert!(ch.valid);
            check(&ch, &cols, m, eps);
        }
        ch.remove(0);
        check(&ch, &cols, m, eps);
        ch.remove(1);
        check(&ch, &cols, m, eps);
        ch.add(2, &cols, m, eps);
        check(&ch, &cols, m, eps);
        assert_eq!(&ch.order[..ch.len], &[3, 4, 2]);
        // And the solve is the regularised least-squares answer.
        let rhs: Vec<f64> = (0..m).map(|i| 1.0 - 0.4 * i as f64).collect();
        let mut z = vec![0.0; n];
        ch.solve(&cols, m, eps, &rhs, &mut z);
        let g: Vec<f64> = [3usize, 4, 2]
            .iter()
            .map(|&f| {
                let res: Vec<f64> = (0..m)
                    .map(|i| [3usize, 4, 2].iter().map(|&h| cols[h * m + i] * z[h]).sum::<f64>() - rhs[i])
                    .collect();
                dot(&cols[f * m..(f + 1) * m], &res) + eps * z[f]
            })
            .collect();
        assert!(g.iter().all(|v| v.abs() < 1e-12), "gradient {g:?}");
    }
}
