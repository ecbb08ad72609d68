//! Exact minimum-norm K from a column-pivoted Householder QR (faer).
//!
//! m ≤ n: Aᵀ P = Q R, so Pᵀ A = Rᵀ Qᵀ and the minimum-norm solution of
//! A k = b is k = Q [R⁻ᵀ Pᵀ b; 0]. m > n: A P = Q R and the least-squares
//! solution is k = P R⁻¹ (Qᵀ b)[..n]. Cost ≈ 2·m²·n flops, no iteration.

use faer::dyn_stack::{MemStack, StackReq};
use faer::linalg::householder;
use faer::linalg::qr::col_pivoting::factor as colpiv;
use faer::linalg::qr::no_pivoting::factor::recommended_block_size;
use faer::linalg::triangular_solve;
use faer::reborrow::*;
use faer::{Conj, MatMut, Par};

/// Block size used for the Householder factor of a `rows × cols` QR.
pub(crate) fn block_size(rows: usize, cols: usize) -> usize {
    if cols <= 64 { 1 } else { recommended_block_size::<f64>(rows, cols) }
}

/// Scratch for any QR solve up to `max_m × max_n`.
pub(crate) fn min_norm_scratch(max_m: usize, max_n: usize) -> StackReq {
    let big = max_m.max(max_n);
    let small = max_m.min(max_n).max(1);
    let bs = block_size(big, small);
    StackReq::any_of(&[
        colpiv::qr_in_place_scratch::<usize, f64>(big, small, bs, Par::Seq, Default::default()),
        householder::apply_block_householder_sequence_on_the_left_in_place_scratch::<f64>(big, bs, 1),
        householder::apply_block_householder_sequence_transpose_on_the_left_in_place_scratch::<f64>(
            big, bs, 1,
        ),
    ])
}

/// Buffers of the QR path, sized once for the largest problem.
#[derive(Debug)]
pub(crate) struct QrBuffers {
    /// The factored matrix (Householder vectors below, R on top).
    pub factor: Vec<f64>,
    pub householder: Vec<f64>,
    pub perm: Vec<usize>,
    pub perm_inv: Vec<usize>,
    pub rhs: Vec<f64>,
}

impl QrBuffers {
    pub fn new(max_m: usize, max_n: usize) -> Self {
        let big = max_m.max(max_n);
        let small = max_m.min(max_n).max(1);
        Self {
            factor: vec![0.0; big * small],
            householder: vec![0.0; block_size(big, small) * small],
            perm: vec![0; small],
            perm_inv: vec![0; small],
            rhs: vec![0.0; big],
        }
    }
}

/// Summary of the factorisation the caller needs afterwards.
#[derive(Debug, Clone, Copy)]
pub(crate) struct QrSummary {
    /// Side of R (min(m, n)).
    pub dim: usize,
    /// Leading dimension of `factor` (rows of the factored matrix).
    pub lead: usize,
    pub rank: usize,
}

/// R (upper triangle of the top `dim × dim` block of the factor).
pub(crate) fn r_factor(buf: &QrBuffers, s: QrSummary) -> super::condition::UpperTriangular<'_> {
    super::condition::UpperTriangular { data: &buf.factor[..s.lead * s.dim], lead: s.lead, dim: s.dim }
}

/// Solve with `rows` = A row-major (m × n). Writes k into `k[..n]`. When the
/// rank is short the values in `k` are meaningless and the caller falls back.
pub(crate) fn min_norm_solve(
    rows: &[f64],
    b: &[f64],
    m: usize,
    n: usize,
    rank_tolerance: f64,
    buf: &mut QrBuffers,
    k: &mut [f64],
    stack: &mut MemStack,
) -> QrSummary {
    let (lead, dim) = if m <= n { (n, m) } else { (m, n) };
    let bs = block_size(lead, dim);
    let factor = &mut buf.factor[..lead * dim];
    if m <= n {
        // Row-major A is already Aᵀ column-major.
        factor.copy_from_slice(&rows[..m * n]);
    } else {
        for i in 0..m {
            for j in 0..n {
                factor[i + j * m] = rows[i * n + j];
            }
        }
    }
    let mut fac = MatMut::from_column_major_slice_mut(factor, lead, dim);
    let mut h = MatMut::from_column_major_slice_mut(&mut buf.householder[..bs * dim], bs, dim);
    let (_, perm) = colpiv::qr_in_place(
        fac.rb_mut(),
        h.rb_mut(),
        &mut buf.perm[..dim],
        &mut buf.perm_inv[..dim],
        Par::Seq,
        stack,
        Default::default(),
    );
    let (fwd, _) = perm.arrays();
    let r00 = fac[(0, 0)].abs();
    let rank = (0..dim).filter(|&i| fac[(i, i)].abs() > rank_tolerance * r00 && r00 > 0.0).count();
    let summary = QrSummary { dim, lead, rank };
    if rank < dim {
        return summary;
    }
    let fac = fac.rb();
    if m <= n {
        let y = &mut buf.rhs[..n];
        for i in 0..m {
            y[i] = b[fwd[i]];
        }
        y[m..].fill(0.0);
        let r = fac.submatrix(0, 0, m, m);
        triangular_solve::solve_lower_triangular_in_place(
            r.transpose(),
            MatMut::from_column_major_slice_mut(&mut y[..m], m, 1),
            Par::Seq,
        );
        householder::apply_block_householder_sequence_on_the_left_in_place_with_conj(
            fac,
            h.rb(),
            Conj::No,
            MatMut::from_column_major_slice_mut(y, n, 1),
            Par::Seq,
            stack,
        );
        k[..n].copy_from_slice(y);
    } else {
        let t = &mut buf.rhs[..m];
        t.copy_from_slice(&b[..m]);
        householder::apply_block_householder_sequence_transpose_on_the_left_in_place_with_conj(
            fac,
            h.rb(),
            Conj::No,
            MatMut::from_column_major_slice_mut(t, m, 1),
            Par::Seq,
            stack,
        );
        let r = fac.submatrix(0, 0, n, n);
        triangular_solve::solve_upper_triangular_in_place(
            r,
            MatMut::from_column_major_slice_mut(&mut t[..n], n, 1),
            Par::Seq,
        );
        for i in 0..n {
            k[fwd[i]] = t[i];
        }
    }
    summary
}
