//! The solver's answer, in buffers preallocated at construction.

use super::SolverCapacity;

/// Which path produced `k`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveMethod {
    /// Consistent, well conditioned, inside the bounds: the exact
    /// minimum-norm (or, overdetermined, least-squares) K from a QR of A.
    Exact,
    /// Bounded least squares |k_j| ≤ k_max (active set, Tikhonov tie-break).
    BoundedLeastSquares,
    /// No constraint rows: K = 0.
    Trivial,
    /// Sparse allocation of a fixed number of slots to candidate centers
    /// (`SolverParams::cycle_slots`).
    Sparse,
}

/// Output of one solve. Vectors never grow past their construction capacity,
/// so refilling them allocates nothing.
#[derive(Debug, Clone)]
pub struct Solution {
    pub(crate) k: Vec<f64>,
    pub(crate) counts: Vec<u16>,
    pub(crate) order: Vec<u16>,
    pub(crate) priority: Vec<f64>,
    pub(crate) achieved_forces: Vec<[f64; 2]>,
    pub(crate) achieved_curls: Vec<f64>,
    /// ‖A·K − b‖ scaled back by μmg/N: force rows in N, curl rows in N/m
    /// (one norm over both).
    pub residual: f64,
    /// Numerical rank of A (from the column-pivoted QR whenever it is
    /// short); 0 when not estimated (a warm-started solve).
    pub rank: usize,
    /// Estimated 2-norm condition number of A (∞ when rank-deficient, 0 when
    /// not estimated: a warm-started solve).
    pub condition: f64,
    /// Centers whose |k_j| is at their bound (within a relative 1e-9).
    pub at_bound: usize,
    /// A sparse cycle's ℓ1 budget was active (false on the paper's cycle).
    pub budget_active: bool,
    /// A bound keeps the request from being met: some bound is active and
    /// `residual` exceeds [`super::SATURATION_TOLERANCE`] of the request's
    /// norm (module doc of `solver`).
    pub saturated: bool,
    pub method: SolveMethod,
    /// Free-block solves of the bounded path (0 on the exact path).
    pub iterations: usize,
    /// The bounded path started from the previous frame's active set and
    /// skipped the factorization of A (`rank` and `condition` are then 0).
    pub warm_started: bool,
    /// False only if the bounded path hit its iteration cap; `k` is then
    /// the best feasible iterate found.
    pub converged: bool,
}

impl Solution {
    pub fn with_capacity(cap: SolverCapacity) -> Self {
        Self {
            k: Vec::with_capacity(cap.centers),
            counts: Vec::with_capacity(cap.centers),
            order: Vec::with_capacity(cap.centers),
            priority: Vec::with_capacity(cap.centers),
            achieved_forces: Vec::with_capacity(cap.parts),
            achieved_curls: Vec::with_capacity(cap.curls),
            residual: 0.0,
            rank: 0,
            condition: 1.0,
            at_bound: 0,
            budget_active: false,
            saturated: false,
            method: SolveMethod::Trivial,
            iterations: 0,
            warm_started: false,
            converged: true,
        }
    }

    /// Rotation intensity per center, in input order.
    pub fn k(&self) -> &[f64] {
        &self.k
    }
    /// Slots each center fills in the cycle, in input order: 1 for every
    /// center in the paper's cycle; 0 for a candidate the sparse allocation
    /// does not play.
    pub fn counts(&self) -> &[u16] {
        &self.counts
    }
    /// Slots of the cycle (Σ counts).
    pub fn slots(&self) -> usize {
        self.counts.iter().map(|&c| usize::from(c)).sum()
    }
    /// Indices of the played centers in play order (descending priority);
    /// center j fills `counts()[j]` consecutive slots.
    pub fn order(&self) -> &[u16] {
        &self.order
    }
    /// Centers this solution has room for (its capacity, fixed at construction).
    pub fn capacity_centers(&self) -> usize {
        self.order.capacity()
    }
    /// Play the centers in `order` instead of the solver's order (the
    /// caller keeps an earlier answer's order over the same slots). Within
    /// capacity this does not allocate; entries beyond it are dropped.
    pub fn hold_order(&mut self, order: &[u16]) {
        let n = order.len().min(self.order.capacity());
        self.order.clear();
        self.order.extend_from_slice(&order[..n]);
    }
    /// ρ_j = |k_j| / min_i |P_i − C_j| per center, in input order.
    pub fn priority(&self) -> &[f64] {
        &self.priority
    }
    /// Average force the model predicts at every part (constrained or not).
    pub fn achieved_forces(&self) -> &[[f64; 2]] {
        &self.achieved_forces
    }
    /// Curl the model predicts at every curl point.
    pub fn achieved_curls(&self) -> &[f64] {
        &self.achieved_curls
    }
}
