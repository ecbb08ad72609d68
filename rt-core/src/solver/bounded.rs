//! Bounded least squares: min ½‖A k − b‖² + ½ε‖k‖² subject to |k_j| ≤ k_max.
//!
//! ADMM on the split k = z, z in the box. The k-update solves
//! (AᵀA + (ε+ρ) I) k = Aᵀb + ρ(z − u) with one Cholesky factor computed up
//! front (through Woodbury on the m×m Gram when m ≤ n). Work is bounded:
//! one m²·n Gram + d³/3 Cholesky, then at most `bounded_max_iterations`
//! iterations of 2·m·n + 2·d² flops (d = min(m, n)). The small ε picks the
//! smallest K among equally good ones (parts closer than the field can
//! resolve), so the answer is unique and deterministic.

use faer::dyn_stack::{MemStack, StackReq};
use faer::linalg::cholesky::llt::{factor as llt, solve as llt_solve};
use faer::linalg::matmul::matmul;
use faer::reborrow::*;
use faer::{Accum, MatMut, MatRef, Par};

pub(crate) fn bounded_scratch(max_m: usize, max_n: usize) -> StackReq {
    let d = max_m.min(max_n).max(1);
    StackReq::any_of(&[
        llt::cholesky_in_place_scratch::<f64>(d, Par::Seq, Default::default()),
        llt_solve::solve_in_place_scratch::<f64>(d, 1, Par::Seq),
    ])
}

#[derive(Debug)]
pub(crate) struct BoundedBuffers {
    gram: Vec<f64>,
    atb: Vec<f64>,
    x: Vec<f64>,
    z: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    t: Vec<f64>,
}

impl BoundedBuffers {
    pub fn new(max_m: usize, max_n: usize) -> Self {
        let d = max_m.min(max_n).max(1);
        Self {
            gram: vec![0.0; d * d],
            atb: vec![0.0; max_n],
            x: vec![0.0; max_n],
            z: vec![0.0; max_n],
            u: vec![0.0; max_n],
            v: vec![0.0; max_n],
            t: vec![0.0; max_m.max(max_n)],
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
    /// Starting point (clamped into the box); may be non-finite.
    pub warm: &'a [f64],
    pub tikhonov: f64,
    pub max_iterations: usize,
    pub tolerance: f64,
}

/// Writes the bounded solution into `k[..n]`, returns iterations used.
pub(crate) fn bounded_solve(
    inp: &BoundedInput<'_>,
    buf: &mut BoundedBuffers,
    k: &mut [f64],
    stack: &mut MemStack,
) -> usize {
    let (m, n) = (inp.m, inp.n);
    let rows = &inp.rows[..m * n];
    let fro2: f64 = rows.iter().map(|a| a * a).sum();
    let scale = fro2 / n as f64;
    let eps = inp.tikhonov * scale;
    let rho = scale;
    let c = eps + rho;
    let woodbury = m <= n;
    let d = if woodbury { m } else { n };

    // Aᵀ as a column-major n × m matrix is the row-major A.
    let at = MatRef::from_column_major_slice(rows, n, m);
    let mut gram = MatMut::from_column_major_slice_mut(&mut buf.gram[..d * d], d, d);
    if woodbury {
        matmul(gram.rb_mut(), Accum::Replace, at.transpose(), at, 1.0, Par::Seq);
    } else {
        matmul(gram.rb_mut(), Accum::Replace, at, at.transpose(), 1.0, Par::Seq);
    }
    for i in 0..d {
        gram[(i, i)] += c;
    }
    // c > 0 makes the matrix SPD; a failure here means non-finite input,
    // which validation has already excluded.
    let _ = llt::cholesky_in_place(gram.rb_mut(), Default::default(), Par::Seq, stack, Default::default());
    let l = gram.rb();

    let atb = &mut buf.atb[..n];
    mat_t_vec(rows, m, n, &inp.b[..m], atb);
    let (x, z, u, v, t) =
        (&mut buf.x[..n], &mut buf.z[..n], &mut buf.u[..n], &mut buf.v[..n], &mut buf.t[..m.max(n)]);
    for j in 0..n {
        let w = inp.warm[j];
        z[j] = if w.is_finite() { w.clamp(-inp.k_max, inp.k_max) } else { 0.0 };
    }
    u.fill(0.0);

    let tol = inp.tolerance * inp.k_max;
    let mut iterations = 0;
    while iterations < inp.max_iterations {
        iterations += 1;
        for j in 0..n {
            v[j] = atb[j] + rho * (z[j] - u[j]);
        }
        if woodbury {
            // x = (v − Aᵀ (AAᵀ + cI)⁻¹ A v) / c
            let tm = &mut t[..m];
            mat_vec(rows, m, n, v, tm);
            llt_solve::solve_in_place(l, MatMut::from_column_major_slice_mut(&mut *tm, m, 1), Par::Seq, stack);
            mat_t_vec(rows, m, n, tm, x);
            for j in 0..n {
                x[j] = (v[j] - x[j]) / c;
            }
        } else {
            x.copy_from_slice(v);
            llt_solve::solve_in_place(l, MatMut::from_column_major_slice_mut(&mut *x, n, 1), Par::Seq, stack);
        }
        let mut primal: f64 = 0.0;
        let mut dual: f64 = 0.0;
        for j in 0..n {
            let z_new = (x[j] + u[j]).clamp(-inp.k_max, inp.k_max);
            dual = dual.max((z_new - z[j]).abs());
            z[j] = z_new;
            u[j] += x[j] - z_new;
            primal = primal.max((x[j] - z_new).abs());
        }
        if primal <= tol && dual <= tol {
            break;
        }
    }
    k[..n].copy_from_slice(z);
    iterations
}

/// out = A v (A row-major m × n).
pub(crate) fn mat_vec(rows: &[f64], m: usize, n: usize, v: &[f64], out: &mut [f64]) {
    for i in 0..m {
        out[i] = rows[i * n..(i + 1) * n].iter().zip(v).map(|(a, x)| a * x).sum();
    }
}

/// out = Aᵀ w (A row-major m × n).
pub(crate) fn mat_t_vec(rows: &[f64], m: usize, n: usize, w: &[f64], out: &mut [f64]) {
    out[..n].fill(0.0);
    for i in 0..m {
        let wi = w[i];
        for (o, a) in out[..n].iter_mut().zip(&rows[i * n..(i + 1) * n]) {
            *o += a * wi;
        }
    }
}
