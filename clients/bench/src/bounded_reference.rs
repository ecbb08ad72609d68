//! The bounded reference of `upm bench solver` and the solver tests: the
//! same box-constrained least squares solved by Clarabel, an interior-point
//! QP solver, at tight tolerances.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus};
use upm_solver::LeastSquaresSystem;

/// min ½‖A k − b‖² + ½ε‖k‖² s.t. |k_j| ≤ k_max, as the QP
/// min ½ kᵀ(AᵀA + εI)k − (Aᵀb)ᵀk with [I; −I] k ≤ k_max.
#[derive(Debug)]
pub struct BoxQp {
    p: CscMatrix<f64>,
    q: Vec<f64>,
    a: CscMatrix<f64>,
    b: Vec<f64>,
}

impl BoxQp {
    pub fn new(sys: &LeastSquaresSystem<'_>, k_max: f64) -> Self {
        let (m, n) = (sys.m, sys.n);
        let at = |i: usize, j: usize| sys.rows[i * n + j];
        let mut dense = vec![vec![0.0; n]; n];
        for (r, row) in dense.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate().skip(r) {
                *v = (0..m).map(|i| at(i, r) * at(i, c)).sum::<f64>() + if r == c { sys.eps } else { 0.0 };
            }
        }
        let q = (0..n).map(|j| -(0..m).map(|i| at(i, j) * sys.b[i]).sum::<f64>()).collect();
        let mut a = vec![vec![0.0; n]; 2 * n];
        for j in 0..n {
            a[j][j] = 1.0;
            a[n + j][j] = -1.0;
        }
        Self { p: CscMatrix::from(&dense), q, a: CscMatrix::from(&a), b: vec![k_max; 2 * n] }
    }

    /// Solve (set-up and factorization included); `None` unless Clarabel
    /// reports solved.
    pub fn solve(&self) -> Option<Vec<f64>> {
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_gap_abs(1e-12)
            .tol_gap_rel(1e-12)
            .tol_feas(1e-12)
            .max_iter(200)
            .build()
            .ok()?;
        let cones = [NonnegativeConeT(self.b.len())];
        let mut solver = DefaultSolver::new(&self.p, &self.q, &self.a, &self.b, &cones, settings).ok()?;
        solver.solve();
        matches!(solver.solution.status, SolverStatus::Solved | SolverStatus::AlmostSolved)
            .then(|| solver.solution.x.clone())
    }
}
