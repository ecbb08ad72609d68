//! faer as the reference dense solver beside UPM's own QR (`upm bench
//! solver`): the minimum-norm solution of A·k = b (m ≤ n, full row rank)
//! from a Householder QR of Aᵀ. With Aᵀ = Q·R, A = Rᵀ·Qᵀ, so k = Q·R⁻ᵀ·b;
//! a tall A (m > n) is plain least squares.
//!
//! Two ways: [`min_norm`], faer's high-level `qr()` / `solve_lstsq`
//! (allocates on every call), and [`MinNormInPlace`], faer's blocked
//! `qr_in_place` with one workspace sized from its `*_scratch()` StackReq,
//! which allocates nothing per solve, as the RT solver thread would need.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::solvers::SolveLstsq;
use faer::linalg::{householder, qr::no_pivoting::factor, triangular_solve};
use faer::{Conj, Mat, MatRef, Par};

/// faer's high-level path: `Aᵀ.qr()`, a triangular solve, `Q_thin · y`.
pub fn min_norm(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let (m, n) = a.shape();
    if m > n {
        return a.qr().solve_lstsq(b);
    }
    let qr = a.transpose().qr();
    let mut y = b.to_owned();
    triangular_solve::solve_lower_triangular_in_place(qr.thin_R().transpose(), y.as_mut(), Par::Seq);
    qr.compute_thin_Q() * y
}

/// faer's low-level path on buffers allocated once for an m × n system
/// (m ≤ n).
pub struct MinNormInPlace {
    /// Aᵀ, then its QR (R above the diagonal, the reflectors below).
    qr: Mat<f64>,
    coeff: Mat<f64>,
    /// b, then R⁻ᵀ·b padded with zeros, then k.
    k: Mat<f64>,
    buf: MemBuffer,
}

impl std::fmt::Debug for MinNormInPlace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MinNormInPlace").field("qr", &self.qr.shape()).finish_non_exhaustive()
    }
}

impl MinNormInPlace {
    fn block(m: usize, n: usize) -> usize {
        factor::recommended_block_size::<f64>(n, m)
    }

    /// Workspace of one solve: the factorization's, or applying Q's.
    pub fn scratch(m: usize, n: usize) -> StackReq {
        let block = Self::block(m, n);
        StackReq::any_of(&[
            factor::qr_in_place_scratch::<f64>(n, m, block, Par::Seq, Default::default()),
            householder::apply_block_householder_sequence_on_the_left_in_place_scratch::<f64>(n, block, 1),
        ])
    }

    pub fn new(m: usize, n: usize) -> Self {
        assert!(m <= n, "the minimum-norm path needs m ≤ n");
        Self {
            qr: Mat::zeros(n, m),
            coeff: Mat::zeros(Self::block(m, n), m),
            k: Mat::zeros(n, 1),
            buf: MemBuffer::new(Self::scratch(m, n)),
        }
    }

    /// k for `a` (m × n) and `b` (m); allocation-free.
    pub fn solve(&mut self, a: MatRef<'_, f64>, b: &[f64]) -> MatRef<'_, f64> {
        let m = b.len();
        self.qr.as_mut().copy_from(a.transpose());
        let stack = MemStack::new(&mut self.buf);
        factor::qr_in_place(self.qr.as_mut(), self.coeff.as_mut(), Par::Seq, stack, Default::default());
        for (i, &bi) in b.iter().enumerate() {
            self.k[(i, 0)] = bi;
        }
        for i in m..self.k.nrows() {
            self.k[(i, 0)] = 0.0;
        }
        let r = self.qr.as_ref().get(..m, ..m);
        triangular_solve::solve_lower_triangular_in_place(
            r.transpose(),
            self.k.as_mut().get_mut(..m, ..),
            Par::Seq,
        );
        householder::apply_block_householder_sequence_on_the_left_in_place_with_conj(
            self.qr.as_ref(),
            self.coeff.as_ref(),
            Conj::No,
            self.k.as_mut(),
            Par::Seq,
            MemStack::new(&mut self.buf),
        );
        self.k.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small underdetermined system with a known minimum-norm answer:
    /// k = Aᵀ(AAᵀ)⁻¹b, by nalgebra.
    #[test]
    fn both_paths_give_the_minimum_norm_solution() {
        let (m, n) = (3, 5);
        let a = Mat::from_fn(m, n, |i, j| ((i * 7 + j * 3) % 5) as f64 - 1.5 + 0.1 * (i + j) as f64);
        let b = Mat::from_fn(m, 1, |i, _| [0.3, -1.2, 0.7][i]);
        let na = nalgebra::DMatrix::from_fn(m, n, |i, j| a[(i, j)]);
        let nb = nalgebra::DVector::from_fn(m, |i, _| b[(i, 0)]);
        let aat_inv = (&na * na.transpose()).try_inverse().expect("full row rank");
        let want = na.transpose() * aat_inv * nb;
        let high = min_norm(a.as_ref(), b.as_ref());
        let mut low = MinNormInPlace::new(m, n);
        let bs = [b[(0, 0)], b[(1, 0)], b[(2, 0)]];
        let low = low.solve(a.as_ref(), &bs);
        for j in 0..n {
            assert!((high[(j, 0)] - want[j]).abs() < 1e-12, "qr(): k[{j}] {} vs {}", high[(j, 0)], want[j]);
            assert!(
                (low[(j, 0)] - want[j]).abs() < 1e-12,
                "qr_in_place: k[{j}] {} vs {}",
                low[(j, 0)],
                want[j]
            );
        }
    }
}
