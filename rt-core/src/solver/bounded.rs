//! Bounded least squares: min ½‖A k − b‖² + ½ε‖k‖² subject to |k_j| ≤ k_max.
//!
//! A feasible active-set method (Lawson & Hanson's NNLS, extended to a box
//! as in Stark & Parker's BVLS): start at k = 0, step toward the optimum of
//! the free block until a variable hits its bound (fix it), and when the
//! free block is optimal release the bound variable whose gradient pulls it
//! inward the most. Every step keeps k feasible and never increases the
//! objective, so stopping at the cap still returns the best point so far;
//! at convergence the KKT conditions hold (to a 1e-10 relative tolerance).
//!
//! The free block is solved as the least-squares problem [A_F; √ε·I] k_F =
//! [r; 0] by Householder QR, never through AᵀA: the normal equations square
//! κ (≈1e12 for close parts) and their KKT tests turn into noise. Work is
//! bounded: at most `bounded_max_iterations` least-squares solves of
//! 2·n_F²·(m + n_F) flops each, plus 4·m·n per release. The small ε picks
//! the smallest K among equally good ones.

use faer::dyn_stack::{MemStack, StackReq};

use super::dense::{axpy, dot};
use faer::linalg::qr::no_pivoting::{factor as qr, solve as qr_solve};
use faer::reborrow::*;
use faer::{MatMut, Par};

use faer::linalg::qr::no_pivoting::factor::recommended_block_size;

/// Householder block size for a `rows × cols` QR: unblocked below 64
/// columns, where blocking only adds set-up.
fn block_size(rows: usize, cols: usize) -> usize {
    if cols <= 64 { 1 } else { recommended_block_size::<f64>(rows, cols) }
}

pub(crate) fn bounded_scratch(max_m: usize, max_n: usize) -> StackReq {
    let rows = max_m + max_n;
    let bs = block_size(rows, max_n);
    StackReq::any_of(&[
        qr::qr_in_place_scratch::<f64>(rows, max_n, bs, Par::Seq, Default::default()),
        qr_solve::solve_lstsq_in_place_scratch::<f64>(rows, max_n, bs, 1, Par::Seq),
    ])
}

#[derive(Debug)]
pub(crate) struct BoundedBuffers {
    aug: Vec<f64>,
    householder: Vec<f64>,
    rhs: Vec<f64>,
    residual: Vec<f64>,
    grad: Vec<f64>,
    target: Vec<f64>,
    free: Vec<usize>,
    state: Vec<i8>,
}

impl BoundedBuffers {
    pub fn new(max_m: usize, max_n: usize) -> Self {
        let rows = max_m + max_n;
        Self {
            aug: vec![0.0; rows * max_n],
            householder: vec![0.0; block_size(rows, max_n) * max_n],
            rhs: vec![0.0; rows],
            residual: vec![0.0; max_m],
            grad: vec![0.0; max_n],
            target: vec![0.0; max_n],
            free: vec![0; max_n],
            state: vec![0; max_n],
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
    pub iterations: usize,
    pub converged: bool,
}

/// Writes the bounded solution into `k[..n]`.
pub(crate) fn bounded_solve(
    inp: &BoundedInput<'_>,
    buf: &mut BoundedBuffers,
    k: &mut [f64],
    stack: &mut MemStack,
) -> BoundedReport {
    let (m, n, k_max) = (inp.m, inp.n, inp.k_max);
    let rows = &inp.rows[..m * n];
    let fro2: f64 = rows.iter().map(|a| a * a).sum();
    // Floor: a degenerate A (parts absurdly far away) still gets a unique K.
    let eps = (inp.tikhonov * fro2 / n as f64).max(1e-300);
    let sys = System { rows, b: &inp.b[..m], m, n, eps };

    // Start feasible at k = 0 with every variable free.
    let k = &mut k[..n];
    k.fill(0.0);
    let state = &mut buf.state[..n];
    state.fill(0);
    let grad = &mut buf.grad[..n];
    sys.gradient(k, &mut buf.residual, grad);
    let tol = grad.iter().fold(0.0f64, |a, g| a.max(g.abs())) * 1e-10 + f64::MIN_POSITIVE;

    let mut report = BoundedReport { iterations: 0, converged: false };
    while report.iterations < inp.max_iterations {
        // Move toward the free block's optimum, stopping at the first bound
        // hit; each pass that stops short fixes at least one variable.
        loop {
            report.iterations += 1;
            let z = &mut buf.target[..n];
            z.copy_from_slice(k);
            let parts = PartitionBuffers {
                aug: &mut buf.aug,
                householder: &mut buf.householder,
                rhs: &mut buf.rhs,
                free: &mut buf.free,
            };
            sys.solve_partition(state, k_max, z, parts, &mut *stack);
            let mut alpha = 1.0f64;
            for j in 0..n {
                if state[j] == 0 && z[j].abs() > k_max {
                    let bound = k_max.copysign(z[j]);
                    alpha = alpha.min(((bound - k[j]) / (z[j] - k[j])).max(0.0));
                }
            }
            for j in 0..n {
                if state[j] == 0 {
                    k[j] += alpha * (z[j] - k[j]);
                    if k[j].abs() >= k_max * (1.0 - 1e-12) {
                        state[j] = if k[j] > 0.0 { 1 } else { -1 };
                        k[j] = k_max.copysign(k[j]);
                    }
                }
            }
            if alpha >= 1.0 || report.iterations >= inp.max_iterations {
                break;
            }
        }
        sys.gradient(k, &mut buf.residual, grad);
        // Release the bound variable whose gradient most wants it inside.
        let mut worst = None;
        let mut worst_pull = tol;
        for j in 0..n {
            let pull = f64::from(state[j]) * grad[j];
            if state[j] != 0 && pull > worst_pull {
                worst_pull = pull;
                worst = Some(j);
            }
        }
        match worst {
            None => {
                report.converged = true;
                break;
            }
            Some(j) => state[j] = 0,
        }
    }
    k.iter_mut().for_each(|v| *v = v.clamp(-k_max, k_max));
    report
}

struct PartitionBuffers<'a> {
    aug: &'a mut [f64],
    householder: &'a mut [f64],
    rhs: &'a mut [f64],
    free: &'a mut [usize],
}

struct System<'a> {
    rows: &'a [f64],
    b: &'a [f64],
    m: usize,
    n: usize,
    eps: f64,
}

impl System<'_> {
    /// γ = Aᵀ(Ak − b) + εk, straight from A (no AᵀA).
    fn gradient(&self, k: &[f64], residual: &mut [f64], out: &mut [f64]) {
        let r = &mut residual[..self.m];
        mat_vec(self.rows, self.m, self.n, k, r);
        r.iter_mut().zip(self.b).for_each(|(v, b)| *v -= b);
        mat_t_vec(self.rows, self.m, self.n, r, out);
        out.iter_mut().zip(k).for_each(|(g, k)| *g += self.eps * k);
    }

    /// Fix the bound variables at ±k_max and solve the free block by QR of
    /// [A_F; √ε·I].
    fn solve_partition(
        &self,
        state: &[i8],
        k_max: f64,
        k: &mut [f64],
        buf: PartitionBuffers<'_>,
        stack: &mut MemStack,
    ) {
        let (m, n) = (self.m, self.n);
        let mut nf = 0;
        for j in 0..n {
            if state[j] == 0 {
                buf.free[nf] = j;
                nf += 1;
            } else {
                k[j] = f64::from(state[j]) * k_max;
            }
        }
        if nf == 0 {
            return;
        }
        let free = &buf.free[..nf];
        let rows_aug = m + nf;
        // Right-hand side: b minus what the bound variables already give.
        let rhs = &mut buf.rhs[..rows_aug];
        for i in 0..m {
            let row = &self.rows[i * n..(i + 1) * n];
            rhs[i] = self.b[i] - (0..n).filter(|&j| state[j] != 0).map(|j| row[j] * k[j]).sum::<f64>();
        }
        rhs[m..].fill(0.0);
        let aug = &mut buf.aug[..rows_aug * nf];
        aug.fill(0.0);
        let sqrt_eps = self.eps.sqrt();
        for (c, &j) in free.iter().enumerate() {
            let col = &mut aug[c * rows_aug..(c + 1) * rows_aug];
            for i in 0..m {
                col[i] = self.rows[i * n + j];
            }
            col[m + c] = sqrt_eps;
        }
        let bs = block_size(rows_aug, nf);
        let mut a = MatMut::from_column_major_slice_mut(aug, rows_aug, nf);
        let mut h = MatMut::from_column_major_slice_mut(&mut buf.householder[..bs * nf], bs, nf);
        qr::qr_in_place(a.rb_mut(), h.rb_mut(), Par::Seq, &mut *stack, Default::default());
        qr_solve::solve_lstsq_in_place(
            a.rb(),
            h.rb(),
            a.rb(),
            MatMut::from_column_major_slice_mut(&mut *rhs, rows_aug, 1),
            Par::Seq,
            stack,
        );
        for (&j, &v) in free.iter().zip(rhs.iter()) {
            k[j] = v;
        }
    }
}

/// out = A v (A row-major m × n).
pub(crate) fn mat_vec(rows: &[f64], m: usize, n: usize, v: &[f64], out: &mut [f64]) {
    for i in 0..m {
        out[i] = dot(&rows[i * n..(i + 1) * n], &v[..n]);
    }
}

/// out = Aᵀ w (A row-major m × n).
pub(crate) fn mat_t_vec(rows: &[f64], m: usize, n: usize, w: &[f64], out: &mut [f64]) {
    out[..n].fill(0.0);
    for i in 0..m {
        axpy(w[i], &rows[i * n..(i + 1) * n], &mut out[..n]);
    }
}
