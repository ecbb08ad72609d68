//! Bounded least squares: min ½‖A k − b‖² + ½ε‖k‖² subject to |k_j| ≤ k_max.
//!
//! **A feasible (primal) active-set method**, as in Stark & Parker's BVLS.
//! Every variable is free or fixed at ±k_max. It starts from the caller's
//! guess (the last frame's active set, the unbounded K clipped, or all
//! free): the guessed free block's optimum, clipped into the box, with what
//! was clipped fixed. From there every step keeps k feasible and never
//! raises the objective, so a good guess is an answer in one iteration and
//! a bad one costs iterations, never correctness. Each iteration solves the
//! free block with the fixed variables at their bounds:
//! - inside the box: take it; at this free optimum, the fixed variable
//!   whose gradient pulls inward the most is released (it is then sure to
//!   move inward), or moved to the opposite bound if its own Newton step
//!   passes it; none: optimal;
//! - outside: take the optimum clipped into the box if that lowers the
//!   objective (a *projected* step, fixing every clipped variable at once),
//!   else step toward it until the first bound and fix that one.
//!
//! **The free block's factor is updated, not recomputed.** R (|F| × |F|)
//! with RᵀR = A_FᵀA_F + εI (`free_cholesky.rs`): freeing a variable borders
//! it, fixing one deletes its column with Givens rotations, O(m·|F| + |F|²)
//! each; steps are solved by corrected semi-normal equations, and r = b −
//! A_B k_B is kept as variables change side. A lost pivot refactors.
//!
//! **The answer never rests on the updates.** When no release remains, the
//! free block is solved again by a fresh Householder QR in whichever form
//! is smaller, never through AᵀA (whose κ² is ~1e20 for close parts), on an
//! r recomputed from scratch:
//! - |F| < m: least squares [A_F; √ε·I] k_F ≈ [r; 0];
//! - else: minimum norm [A_F √ε·I] v = r, k_F = v[..|F|], from the QR of
//!   [A_Fᵀ; √ε·I];
//!
//! and the KKT conditions are checked on that solution (the iteration goes
//! on if they fail). Both forms are backward stable, and the answer depends
//! only on the final active set: a warm start gives the cold answer bit for
//! bit when both end on the same set.
//!
//! Work is bounded: at most `max_iterations` iterations, each one update
//! and one solve with R plus O(m·n) for the gradient and objective, and a
//! fresh QR of 2·d²·(m + |F|) flops (d = min(m, |F|)) at the start, to
//! confirm, and after a lost pivot. The small ε picks the smallest K among
//! equally good ones.

use super::dense::{axpy, dot};
use super::free_cholesky::FreeCholesky;
use super::pivoted_qr::PivotedQr;

#[derive(Debug)]
pub(crate) struct BoundedBuffers {
    /// A by columns: column j at `[j·m, (j+1)·m)`.
    cols: Vec<f64>,
    /// The free block's matrix in its smaller form, column-major, factored
    /// in place.
    factor: Vec<f64>,
    tau: Vec<f64>,
    perm: Vec<usize>,
    norms: Vec<f64>,
    norms_ref: Vec<f64>,
    work: Vec<f64>,
    rhs: Vec<f64>,
    residual: Vec<f64>,
    target: Vec<f64>,
    trial: Vec<f64>,
    free: Vec<usize>,
    chol: FreeCholesky,
    /// Per variable: 0 free, ±1 fixed at ±k_max. The caller writes the
    /// starting guess here; after a solve it holds the final active set.
    pub state: Vec<i8>,
}

impl BoundedBuffers {
    pub fn new(max_m: usize, max_n: usize) -> Self {
        let (m, n) = (max_m.max(1), max_n.max(1));
        let d = m.max(n);
        Self {
            cols: vec![0.0; m * n],
            factor: vec![0.0; (n + m) * d],
            tau: vec![0.0; d],
            perm: vec![0; d],
            norms: vec![0.0; d],
            norms_ref: vec![0.0; d],
            work: vec![0.0; n + m],
            rhs: vec![0.0; m],
            residual: vec![0.0; m],
            target: vec![0.0; n],
            trial: vec![0.0; n],
            free: vec![0; n],
            chol: FreeCholesky::new(m, n),
            state: vec![0; n],
        }
    }
}

pub(crate) struct BoundedInput<'a> {
    /// A row-major, m × n.
    pub rows: &'a [f64],
    pub b: &'a [f64],
    pub m: usize,
    pub n: usize,
    pub k_max: f64,
    pub tikhonov: f64,
    pub max_iterations: usize,
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct BoundedReport {
    /// Free-block solves.
    pub iterations: usize,
    pub converged: bool,
    /// Bounds active at the answer.
    pub active: usize,
}

/// Solves from the guess in `buf.state[..n]` and writes the bounded
/// solution into `k[..n]`; `buf.state` then holds its active set.
pub(crate) fn bounded_solve(
    inp: &BoundedInput<'_>,
    buf: &mut BoundedBuffers,
    k: &mut [f64],
) -> BoundedReport {
    let (m, n, k_max) = (inp.m, inp.n, inp.k_max);
    let rows = &inp.rows[..m * n];
    let cols = &mut buf.cols[..m * n];
    for i in 0..m {
        for j in 0..n {
            cols[j * m + i] = rows[i * n + j];
        }
    }
    let block = FreeBlock {
        cols: &buf.cols[..m * n],
        b: &inp.b[..m],
        m,
        n,
        eps: super::system::tikhonov_eps(rows, n, inp.tikhonov),
        k_max,
    };
    let mut qr = QrBuffers {
        factor: &mut buf.factor,
        tau: &mut buf.tau,
        perm: &mut buf.perm,
        norms: &mut buf.norms,
        norms_ref: &mut buf.norms_ref,
        work: &mut buf.work,
        free: &mut buf.free,
        chol: &mut buf.chol,
    };
    qr.chol.valid = false;
    let mut it = Iterate { state: &mut buf.state[..n], k: &mut k[..n], rhs: &mut buf.rhs[..m] };
    let z = &mut buf.target[..n];
    let trial = &mut buf.trial[..n];
    let residual = &mut buf.residual[..m];
    // Release threshold: relative to the gradient at k = 0, γ = −Aᵀb.
    let tol =
        (0..n).map(|j| dot(block.col(j), block.b).abs()).fold(0.0f64, f64::max) * 1e-10 + f64::MIN_POSITIVE;

    // Start: the guessed free block's optimum, clipped into the box.
    let mut report = BoundedReport { iterations: 1, converged: false, active: 0 };
    block.refresh_rhs(it.state, it.rhs);
    let mut rhs_fresh = true;
    // The last solve is the canonical answer for its active set: a fresh
    // QR in the smaller form on an r computed from scratch.
    let mut canonical = block.solve(it.state, z, it.rhs, &mut qr, false);
    let mut at_optimum = true;
    for j in 0..n {
        if it.state[j] != 0 {
            it.k[j] = f64::from(it.state[j]) * k_max;
        } else if z[j].abs() > k_max {
            block.fix(&mut it, qr.chol, j, z[j]);
            (at_optimum, rhs_fresh) = (false, false);
        } else {
            it.k[j] = z[j];
        }
    }
    let mut f_k = block.objective(it.state, it.k, it.rhs, residual);
    let mut confirm = false;
    // Each pass steps toward the free block's optimum or, there, releases
    // one bound or stops.
    loop {
        if at_optimum {
            // γ_j = a_jᵀ(A k − b) + ε k_j on the fixed variables; release the
            // one that most wants inside (it is then sure to move inward).
            block.residual(it.state, it.k, it.rhs, residual);
            let mut worst = None;
            let mut worst_pull = tol;
            for j in 0..n {
                if it.state[j] != 0 {
                    let pull = f64::from(it.state[j]) * (dot(block.col(j), residual) + block.eps * it.k[j]);
                    if pull > worst_pull {
                        (worst, worst_pull) = (Some(j), pull);
                    }
                }
            }
            match worst {
                // If even alone (the others held) it would run past the
                // opposite bound, move it there: the objective falls all
                // the way, and the sign change costs one solve, not a
                // release and a re-fix.
                Some(j) if flips_over(block.col(j), block.eps, it.k[j], worst_pull, k_max) => {
                    block.flip(&mut it, j);
                    rhs_fresh = false;
                    f_k = block.objective(it.state, it.k, it.rhs, residual);
                }
                Some(j) => {
                    block.release(&mut it, qr.chol, j);
                    rhs_fresh = false;
                }
                None if canonical && rhs_fresh => {
                    report.converged = true;
                    break;
                }
                // Optimal on the incrementally kept r and the updated factor:
                // confirm once with both recomputed from scratch, so that the
                // answer depends on the final active set only.
                None => {
                    block.refresh_rhs(it.state, it.rhs);
                    (rhs_fresh, confirm) = (true, true);
                }
            }
        }
        if report.iterations >= inp.max_iterations {
            break;
        }
        report.iterations += 1;
        canonical = block.solve(it.state, z, it.rhs, &mut qr, confirm);
        confirm = false;
        let free = |j: &usize| it.state[*j] == 0;
        if (0..n).filter(free).all(|j| z[j].abs() <= k_max) {
            // The free optimum is inside: take it whole.
            (0..n).filter(|&j| it.state[j] == 0).for_each(|j| it.k[j] = z[j]);
            f_k = block.objective(it.state, it.k, it.rhs, residual);
            at_optimum = true;
            continue;
        }
        at_optimum = false;
        rhs_fresh = false;
        // Projected step: the free optimum clipped into the box, kept if it
        // lowers the objective (it fixes every clipped variable at once).
        trial.copy_from_slice(it.k);
        (0..n).filter(|&j| it.state[j] == 0).for_each(|j| trial[j] = z[j].clamp(-k_max, k_max));
        let f_trial = block.objective(it.state, trial, it.rhs, residual);
        if f_trial < f_k {
            for j in 0..n {
                if it.state[j] == 0 && z[j].abs() > k_max {
                    block.fix(&mut it, qr.chol, j, z[j]);
                } else if it.state[j] == 0 {
                    it.k[j] = trial[j];
                }
            }
            f_k = f_trial;
            continue;
        }
        // Otherwise step toward it until the first bound (never raises the
        // objective; each such step fixes at least one variable).
        let mut alpha = 1.0f64;
        for j in 0..n {
            if it.state[j] == 0 && z[j].abs() > k_max {
                alpha = alpha.min(((k_max.copysign(z[j]) - it.k[j]) / (z[j] - it.k[j])).max(0.0));
            }
        }
        for j in 0..n {
            if it.state[j] == 0 {
                let next = it.k[j] + alpha * (z[j] - it.k[j]);
                if next.abs() >= k_max * (1.0 - 1e-12) {
                    block.fix(&mut it, qr.chol, j, next);
                } else {
                    it.k[j] = next;
                }
            }
        }
        f_k = block.objective(it.state, it.k, it.rhs, residual);
    }
    it.k.iter_mut().for_each(|v| *v = v.clamp(-k_max, k_max));
    report.active = it.state.iter().filter(|s| **s != 0).count();
    report
}

/// A fixed variable at ±k_max whose gradient pulls inward by `pull`
/// (= |γ_j|): does its own Newton step, k_j ∓ pull/(‖a_j‖² + ε), pass
/// the opposite bound?
fn flips_over(a: &[f64], eps: f64, k: f64, pull: f64, k_max: f64) -> bool {
    pull / (dot(a, a) + eps) > k.abs() + k_max
}

/// The iterate: which variables are fixed, k, and r = b − A_B k_B, kept
/// up to date as variables change side (m flops each).
struct Iterate<'a> {
    state: &'a mut [i8],
    k: &'a mut [f64],
    rhs: &'a mut [f64],
}

/// The system and how to solve its free block.
struct FreeBlock<'a> {
    cols: &'a [f64],
    b: &'a [f64],
    m: usize,
    n: usize,
    eps: f64,
    k_max: f64,
}

struct QrBuffers<'a> {
    factor: &'a mut [f64],
    tau: &'a mut [f64],
    perm: &'a mut [usize],
    norms: &'a mut [f64],
    norms_ref: &'a mut [f64],
    work: &'a mut [f64],
    free: &'a mut [usize],
    chol: &'a mut FreeCholesky,
}

impl FreeBlock<'_> {
    fn col(&self, j: usize) -> &[f64] {
        &self.cols[j * self.m..(j + 1) * self.m]
    }

    /// Fix variable j at the bound on `toward`'s side.
    fn fix(&self, it: &mut Iterate<'_>, chol: &mut FreeCholesky, j: usize, toward: f64) {
        it.state[j] = if toward > 0.0 { 1 } else { -1 };
        it.k[j] = self.k_max.copysign(toward);
        axpy(-it.k[j], self.col(j), it.rhs);
        if chol.valid {
            chol.remove(j);
        }
    }

    /// Move fixed variable j to the opposite bound (the free set, and so
    /// the factor, stay as they are).
    fn flip(&self, it: &mut Iterate<'_>, j: usize) {
        axpy(2.0 * it.k[j], self.col(j), it.rhs);
        it.state[j] = -it.state[j];
        it.k[j] = -it.k[j];
    }

    fn release(&self, it: &mut Iterate<'_>, chol: &mut FreeCholesky, j: usize) {
        axpy(it.k[j], self.col(j), it.rhs);
        it.state[j] = 0;
        if chol.valid {
            chol.add(j, self.cols, self.m, self.eps);
        }
    }

    /// r = b − A_B k_B from scratch.
    fn refresh_rhs(&self, state: &[i8], rhs: &mut [f64]) {
        rhs.copy_from_slice(self.b);
        for j in 0..self.n {
            if state[j] != 0 {
                axpy(-f64::from(state[j]) * self.k_max, self.col(j), rhs);
            }
        }
    }

    /// out = A k − b = A_F k_F − r (m·|F| flops).
    fn residual(&self, state: &[i8], k: &[f64], rhs: &[f64], out: &mut [f64]) {
        out.iter_mut().zip(rhs).for_each(|(o, r)| *o = -r);
        for j in 0..self.n {
            if state[j] == 0 {
                axpy(k[j], self.col(j), out);
            }
        }
    }

    /// ½‖A k − b‖² + ½ε‖k‖² (`scratch` gets the residual).
    fn objective(&self, state: &[i8], k: &[f64], rhs: &[f64], scratch: &mut [f64]) -> f64 {
        self.residual(state, k, rhs, scratch);
        0.5 * (dot(scratch, scratch) + self.eps * dot(k, k))
    }

    /// z_F ← the free block's optimum with the fixed variables at their
    /// bounds: from the updated factor, or by a fresh QR of [A_F; √ε·I]
    /// (which renews it), or, to `confirm` an answer, by a fresh QR in
    /// the smaller form (module doc). True when it was that canonical
    /// fresh QR in the smaller form.
    fn solve(&self, state: &[i8], z: &mut [f64], rhs: &[f64], qr: &mut QrBuffers<'_>, confirm: bool) -> bool {
        let m = self.m;
        let mut nf = 0;
        for j in 0..self.n {
            if state[j] == 0 {
                qr.free[nf] = j;
                nf += 1;
            }
        }
        if nf == 0 {
            qr.chol.load(&[], 1, &[]);
            return true;
        }
        if qr.chol.valid && !confirm {
            qr.chol.solve(self.cols, m, self.eps, rhs, z);
            return false;
        }
        let sqrt_eps = self.eps.sqrt();
        let lead = nf + m;
        let v = &mut qr.work[..lead];
        if nf < m || !confirm {
            // [A_F; √ε·I] (m + |F|) × |F|, column c = [a_{F_c}; √ε·e_c]:
            // also the factor the updates continue from.
            let factor = &mut qr.factor[..lead * nf];
            factor.fill(0.0);
            for (c, &j) in qr.free[..nf].iter().enumerate() {
                let col = &mut factor[c * lead..(c + 1) * lead];
                col[..m].copy_from_slice(self.col(j));
                col[m + c] = sqrt_eps;
            }
            let mut f = PivotedQr {
                a: factor,
                rows: lead,
                cols: nf,
                tau: &mut qr.tau[..nf],
                perm: &mut qr.perm[..nf],
            };
            f.factor(&mut qr.norms[..nf], &mut qr.norms_ref[..nf], false);
            v[..m].copy_from_slice(rhs);
            v[m..].fill(0.0);
            f.apply_qt(v);
            f.solve_r(v);
            qr.chol.load(f.a, lead, &qr.free[..nf]);
        } else {
            // [A_Fᵀ; √ε·I] (|F| + m) × m, column i = [row i of A_F; √ε·e_i].
            let factor = &mut qr.factor[..lead * m];
            factor.fill(0.0);
            for (c, &j) in qr.free[..nf].iter().enumerate() {
                for (i, a) in self.col(j).iter().enumerate() {
                    factor[c + i * lead] = *a;
                }
            }
            for i in 0..m {
                factor[nf + i + i * lead] = sqrt_eps;
            }
            let mut f =
                PivotedQr { a: factor, rows: lead, cols: m, tau: &mut qr.tau[..m], perm: &mut qr.perm[..m] };
            f.factor(&mut qr.norms[..m], &mut qr.norms_ref[..m], false);
            v[..m].copy_from_slice(rhs);
            v[m..].fill(0.0);
            f.solve_rt(v);
            f.apply_q(v);
            qr.chol.valid = false;
        }
        for (c, &j) in qr.free[..nf].iter().enumerate() {
            z[j] = v[c];
        }
        nf < m || confirm
    }
}

/// out = A v (A row-major m × n).
pub(crate) fn mat_vec(rows: &[f64], m: usize, n: usize, v: &[f64], out: &mut [f64]) {
    for i in 0..m {
        out[i] = dot(&rows[i * n..(i + 1) * n], &v[..n]);
    }
}
