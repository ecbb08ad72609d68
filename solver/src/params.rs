//! Solver tunables and capacities (faer style: a `Params` struct with defaults).

/// Largest problem a [`crate::Solver`] accepts; fixed at construction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolverCapacity {
    pub parts: usize,
    pub curls: usize,
    pub centers: usize,
}

impl SolverCapacity {
    /// The product's guaranteed capacity.
    pub const DEFAULT: Self = Self { parts: 64, curls: 16, centers: 192 };

    pub fn max_rows(&self) -> usize {
        2 * self.parts + self.curls
    }
}

impl Default for SolverCapacity {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Numerical tunables. Defaults are what the tests and benchmarks use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverParams {
    /// Diagonal entries of R below `rank_tolerance · max |Rᵢᵢ|` count as rank
    /// loss.
    pub rank_tolerance: f64,
    /// Above this estimated κ₂ the exact min-norm path is not trusted. The
    /// estimate is a lower bound (≥ 0.72 × the true κ₂ in the SVD tests),
    /// so the effective gate sits up to ~1.4× higher.
    pub max_condition: f64,
    /// A constrained point closer than this to a center is an input error (m).
    pub min_center_distance: f64,
    /// Power/inverse iterations for the κ₂ estimate (fixed: bounded work).
    pub condition_iterations: usize,
    /// The κ₂ estimate stops once a step changes it by less than this
    /// (relative).
    pub condition_tolerance: f64,
    /// Cap on least-squares solves in the bounded fallback.
    pub bounded_max_iterations: usize,
    /// Tikhonov weight (relative to ‖A‖²_F / N) that picks the smallest K
    /// among equally good bounded solutions.
    pub tikhonov: f64,
    /// Start a saturated frame's bounded solve from the last frame's active
    /// set when centers and rows match (module doc of `solver`).
    pub warm_start: bool,
    /// 0: the paper's cycle, one slot per center. N > 0: the centers are
    /// candidates and a cycle is N slots, allocated sparsely (`sparse.rs`).
    pub cycle_slots: usize,
    /// Cap on the sparse allocation's gradient iterations.
    pub sparse_iterations: usize,
    /// The sparse allocation plays no center closer than this to a
    /// constrained point (m): there the field turns around within a
    /// position error, so a part would be pushed every which way.
    pub sparse_keep_out: f64,
    /// The sparse allocation's ℓ1 weight, relative to ‖Aᵀb‖∞.
    pub sparse_shrink: f64,
}

impl Default for SolverParams {
    fn default() -> Self {
        Self {
            rank_tolerance: 1e-12,
            max_condition: 1e10,
            min_center_distance: 1e-6,
            condition_iterations: 12,
            condition_tolerance: 1e-2,
            bounded_max_iterations: 400,
            tikhonov: 1e-9,
            warm_start: true,
            cycle_slots: 0,
            sparse_iterations: 300,
            sparse_keep_out: 0.1,
            sparse_shrink: 0.003,
        }
    }
}
