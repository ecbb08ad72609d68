//! The least-squares system a solve worked on, for references and
//! benchmarks that must pose exactly the same problem.

/// A (row-major m × n) and b scaled by N/μmg as the solver assembles them
/// (row order in `assemble.rs`), and the Tikhonov weight ε of the bounded
/// path: the bounded path minimises [`LeastSquaresSystem::objective`]
/// subject to |k_j| ≤ k_max.
#[derive(Debug, Clone, Copy)]
pub struct LeastSquaresSystem<'a> {
    pub rows: &'a [f64],
    pub b: &'a [f64],
    pub m: usize,
    pub n: usize,
    pub eps: f64,
}

impl LeastSquaresSystem<'_> {
    /// ½‖A k − b‖² + ½ε‖k‖².
    pub fn objective(&self, k: &[f64]) -> f64 {
        let mut sum = 0.0;
        for i in 0..self.m {
            let row = &self.rows[i * self.n..(i + 1) * self.n];
            let r: f64 = row.iter().zip(k).map(|(a, k)| a * k).sum::<f64>() - self.b[i];
            sum += r * r;
        }
        0.5 * sum + 0.5 * self.eps * k.iter().map(|v| v * v).sum::<f64>()
    }

    /// Gradient Aᵀ(A k − b) + ε k.
    pub fn gradient(&self, k: &[f64]) -> Vec<f64> {
        let mut g: Vec<f64> = k.iter().map(|v| self.eps * v).collect();
        for i in 0..self.m {
            let row = &self.rows[i * self.n..(i + 1) * self.n];
            let r: f64 = row.iter().zip(k).map(|(a, k)| a * k).sum::<f64>() - self.b[i];
            g.iter_mut().zip(row).for_each(|(g, a)| *g += a * r);
        }
        g
    }
}

/// ε = tikhonov · ‖A‖²_F / n, floored so a degenerate A (parts absurdly
/// far away) still gets a unique K.
pub(crate) fn tikhonov_eps(rows: &[f64], n: usize, tikhonov: f64) -> f64 {
    let fro2: f64 = rows.iter().map(|a| a * a).sum();
    (tikhonov * fro2 / n as f64).max(1e-300)
}
