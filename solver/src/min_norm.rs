//! Exact minimum-norm K from a Householder QR, column-pivoted on request.
//!
//! m ≤ n: Aᵀ P = Q R, so Pᵀ A = Rᵀ Qᵀ and the minimum-norm solution of
//! A k = b is k = Q [R⁻ᵀ Pᵀ b; 0]. m > n: A P = Q R and the least-squares
//! solution is k = P R⁻¹ (Qᵀ b)[..n]. Cost ≈ 2·m²·n flops, no iteration.
//! Needs no `MemStack`: every buffer lives in [`QrBuffers`].

use super::pivoted_qr::PivotedQr;

/// Buffers of the QR path, sized once for the largest problem.
#[derive(Debug)]
pub(crate) struct QrBuffers {
    /// The factored matrix (Householder vectors below, R on top).
    pub factor: Vec<f64>,
    tau: Vec<f64>,
    perm: Vec<usize>,
    norms: Vec<f64>,
    norms_ref: Vec<f64>,
    rhs: Vec<f64>,
}

impl QrBuffers {
    pub fn new(max_m: usize, max_n: usize) -> Self {
        let big = max_m.max(max_n);
        let small = max_m.min(max_n).max(1);
        Self {
            factor: vec![0.0; big * small],
            tau: vec![0.0; small],
            perm: vec![0; small],
            norms: vec![0.0; small],
            norms_ref: vec![0.0; small],
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

/// How to factor: with column pivoting or not, and where the rank ends.
#[derive(Debug, Clone, Copy)]
pub(crate) struct QrOptions {
    pub rank_tolerance: f64,
    pub pivot: bool,
}

/// Solve with `rows` = A row-major (m × n). Writes k into `k[..n]`. When the
/// rank is short the values in `k` are meaningless and the caller falls back.
pub(crate) fn min_norm_solve(
    rows: &[f64],
    b: &[f64],
    m: usize,
    n: usize,
    options: QrOptions,
    buf: &mut QrBuffers,
    k: &mut [f64],
) -> QrSummary {
    let QrOptions { rank_tolerance, pivot } = options;
    let (lead, dim) = if m <= n { (n, m) } else { (m, n) };
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
    let mut qr =
        PivotedQr { a: factor, rows: lead, cols: dim, tau: &mut buf.tau[..dim], perm: &mut buf.perm[..dim] };
    qr.factor(&mut buf.norms, &mut buf.norms_ref, pivot);
    // With pivoting |r₀₀| is the largest pivot; without, take the largest.
    let r_max = (0..dim).map(|i| qr.r_diag(i).abs()).fold(0.0, f64::max);
    let rank = (0..dim).filter(|&i| qr.r_diag(i).abs() > rank_tolerance * r_max && r_max > 0.0).count();
    let summary = QrSummary { dim, lead, rank };
    if rank < dim {
        return summary;
    }
    if m <= n {
        let y = &mut buf.rhs[..n];
        for i in 0..m {
            y[i] = b[qr.perm[i]];
        }
        y[m..].fill(0.0);
        qr.solve_rt(y);
        qr.apply_q(y);
        k[..n].copy_from_slice(y);
    } else {
        let t = &mut buf.rhs[..m];
        t.copy_from_slice(&b[..m]);
        qr.apply_qt(t);
        qr.solve_r(t);
        for i in 0..n {
            k[qr.perm[i]] = t[i];
        }
    }
    summary
}
