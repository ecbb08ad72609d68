//! Force synthesis: desired per-part forces and curls → rotation
//! intensities k_j of one closed plate motion (paper §2–3, ARCHITECTURE.md §2).
//!
//! [`Solver::new`] allocates every buffer once for a [`SolverCapacity`];
//! [`Solver::solve`] then allocates nothing, runs single-threaded
//! (bit-identical for the same input and the same previous frame) and does
//! bounded work:
//!
//! 1. validate and assemble A (m × n) and b;
//! 2. Householder QR → rank, κ₂ estimate, exact minimum-norm K; the QR is
//!    redone with column pivoting (rank-revealing) only when the rank looks
//!    short or κ₂ exceeds `max_condition`;
//! 3. if K is inside |k_j| ≤ k_max, full rank and κ₂ ≤ `max_condition`:
//!    done (exact path);
//! 4. otherwise bounded least squares by a feasible active-set method with
//!    an updated factorization, started from the exact K clipped into the
//!    box, at most `bounded_max_iterations` iterations (flops in
//!    `bounded.rs`);
//! 5. achieved forces/curls, residual, priorities and play order.
//!
//! **Residual and saturation.** `residual` is ‖A·K − b‖ scaled back by
//! μmg/N: force rows in N, curl rows in N/m, one Euclidean norm over both.
//! `at_bound` counts the centers whose |k_j| is at their bound (within a
//! relative 1e-9). `saturated` says a bound keeps the request from being
//! met: some bound is active (a center at its bound, or a sparse cycle's
//! ℓ1 budget) *and* `residual` > [`SATURATION_TOLERANCE`] · ‖b‖ +
//! [`SATURATION_FLOOR`], ‖b‖ being the request's norm in the same units
//! (forces in N and curls in N/m). A bound that is active while the request
//! is met shows in `at_bound` alone; a zero request is never saturated.
//!
//! **Shaped parts** (`ForceConstraint::shape`, `CurlConstraint::shape`):
//! their rows are the rotation's friction averaged over the part's contact
//! patch, at rest (`shape.rs`), not the field at the centre; a point keeps
//! the paper's rows bit for bit. A part's own motion is corrected for
//! around the solver, not in it (`upm_motion::PartDynamics`).
//!
//! **Per-center bounds** (`Problem::k_bounds`, what each rotation can play
//! on the rig): by a change of variable. Column j of A is scaled by s_j =
//! u_j / u_max (u_j its bound), every path above solves for k'_j = k_j / s_j
//! under the one bound u_max, and k_j = s_j·k'_j. The exact path's minimum
//! norm is then Σ (k_j / s_j)²: a weak center is used less. With every
//! bound equal, s_j = 1 and nothing is scaled.
//!
//! **Sparse cycles** (`SolverParams::cycle_slots` = N > 0) replace steps
//! 2–4: the centers are candidates, and a cycle of N slots goes to the few
//! the request needs, a center filling as many slots as its share
//! (`sparse.rs`: ℓ1-budgeted least squares, then the bounded solver above
//! on the played columns). `Solution::counts` says how many slots each
//! center fills; the paper's cycle is N = 0, one slot per center.
//!
//! **Warm start.** Consecutive camera frames ask nearly the same question,
//! and in a saturated frame the bounded path is the whole cost. When the
//! last solve was bounded, converged with some bound active, and this one
//! has the same centers and the same rows (`SolverParams::warm_start`),
//! steps 2–3 are skipped and the bounded solve starts from the last
//! active set. The answer is the same optimum (it depends only on the final
//! active set, `bounded.rs`); such a solve does not factor A, so it reports
//! `rank` and `condition` as 0 (not estimated). If it ends with no bound
//! active, the solve is redone from step 2, so an unsaturated frame always
//! gets the exact path.

// Index loops mirror the matrix formulas; buffers are passed separately so
// each routine borrows only what it needs.
#![allow(clippy::needless_range_loop)]

mod assemble;
mod bounded;
mod condition;
mod dense;
mod error;
pub mod field;
mod free_cholesky;
mod min_norm;
mod order;
mod params;
mod pivoted_qr;
mod problem;
mod reach;
mod shape;
mod solution;
mod sparse;
mod system;
mod validate;

pub use error::{InputField, MAX_INPUT_MAGNITUDE, SolveError};
pub use params::{SolverCapacity, SolverParams};
pub use problem::{CurlConstraint, ForceConstraint, Problem};
pub use reach::{CENTER_CLEARANCE, MaxForce, max_force_at, max_force_in, max_force_on_plate};
pub use shape::{MAX_PATCH_POINTS, MAX_SHAPE_VERTICES, PartShape, PatchPoints, ShapeError, wrench_row};
pub use solution::{Solution, SolveMethod};
pub use system::LeastSquaresSystem;

use bounded::{BoundedBuffers, BoundedInput};
use min_norm::QrBuffers;
use sparse::SparseBuffers;

/// Relative tolerance of [`Solution::saturated`]: a request is met when
/// the residual is at most this share of its norm (module doc).
pub const SATURATION_TOLERANCE: f64 = 1e-3;

/// Absolute floor of that tolerance (N, or N/m on curl rows): rounding on
/// a (near) zero request is not saturation.
pub const SATURATION_FLOOR: f64 = 1e-12;

/// The allocation-free force-synthesis solver.
pub struct Solver {
    cap: SolverCapacity,
    params: SolverParams,
    rows: Vec<f64>,
    b: Vec<f64>,
    residual: Vec<f64>,
    qr: QrBuffers,
    bounded: BoundedBuffers,
    exact_k: Vec<f64>,
    cond_v: Vec<f64>,
    cond_w: Vec<f64>,
    cond_u: Vec<f64>,
    min_dist: Vec<f64>,
    center_x: Vec<f64>,
    center_y: Vec<f64>,
    cond_diag: Vec<f64>,
    sparse: SparseBuffers,
    remainder: Vec<f64>,
    /// s_j = u_j / u_max of the per-center bounds (module doc).
    column_scale: Vec<f64>,
    /// The played centers' scaled columns for the sparse path's polish.
    compact: Vec<f64>,
    played: Vec<u16>,
    warm: WarmStart,
    /// Shape of the last assembled system (for [`Solver::last_system`]).
    last_shape: (usize, usize),
}

/// Whether the active set the last bounded solve left in the bounded
/// buffers may start the next frame, and the layout it belongs to.
#[derive(Debug)]
struct WarmStart {
    valid: bool,
    rows: usize,
    force_rows: usize,
    centers: Vec<[f64; 2]>,
}

impl WarmStart {
    fn matches(&self, problem: &Problem<'_>, m: usize) -> bool {
        self.valid
            && self.rows == m
            && self.force_rows == problem.force_rows()
            && self.centers.len() == problem.centers.len()
            && self.centers.iter().zip(problem.centers).all(|(a, b)| a[0] == b[0] && a[1] == b[1])
    }
}

impl core::fmt::Debug for Solver {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Solver").field("cap", &self.cap).field("params", &self.params).finish_non_exhaustive()
    }
}

impl Solver {
    /// Allocates everything a solve of up to `cap` will need.
    pub fn new(cap: SolverCapacity, params: SolverParams) -> Self {
        let (m, n) = (cap.max_rows(), cap.centers);
        Self {
            cap,
            params,
            rows: vec![0.0; m * n],
            b: vec![0.0; m],
            residual: vec![0.0; m],
            qr: QrBuffers::new(m, n),
            bounded: BoundedBuffers::new(m, n),
            exact_k: vec![0.0; n],
            cond_v: vec![0.0; m.min(n)],
            cond_w: vec![0.0; m.min(n)],
            cond_u: vec![0.0; m.min(n)],
            min_dist: vec![0.0; n],
            center_x: vec![0.0; n],
            center_y: vec![0.0; n],
            cond_diag: vec![0.0; m.min(n)],
            sparse: SparseBuffers::new(m, n),
            remainder: vec![0.0; n],
            column_scale: vec![1.0; n],
            compact: vec![0.0; m * n],
            played: Vec::with_capacity(n),
            warm: WarmStart { valid: false, rows: 0, force_rows: 0, centers: Vec::with_capacity(n) },
            last_shape: (0, 0),
        }
    }

    pub fn capacity(&self) -> SolverCapacity {
        self.cap
    }

    pub fn params(&self) -> &SolverParams {
        &self.params
    }

    /// Run two full-capacity solves (exact and bounded path) on the calling
    /// thread, so that every buffer page is touched and every SIMD dispatch
    /// resolved before the first real frame. A real-time thread calls this
    /// once at start-up. Returns false if a warm-up solve failed. Forgets
    /// the warm start it leaves behind.
    pub fn warm_up(&mut self) -> bool {
        let cap = self.cap;
        let mut out = self.new_solution();
        let mut centers = vec![[0.0; 2]; cap.centers];
        for (j, c) in centers.iter_mut().enumerate() {
            let a = j as f64 * 2.399_963; // golden angle: spread, never repeated
            let r = 2.0 + 0.5 * ((j as f64) * 0.37).sin();
            *c = [r * a.cos(), r * a.sin()];
        }
        // The disc table is only read near a center (within 64 radii), which
        // the parts below never are: build it here, not on a real frame.
        shape::build_tables();
        let mut ok = true;
        for force in [1e-4, 10.0] {
            let parts: Vec<_> = (0..cap.parts)
                .map(|i| {
                    let a = i as f64 * 2.399_963;
                    let r = 0.8 * ((i as f64 + 0.5) / cap.parts as f64).sqrt();
                    // Every other part a disc: the shaped rows on the warm path.
                    let shape = if i % 2 == 0 { PartShape::Point } else { PartShape::Disc { radius: 0.01 } };
                    ForceConstraint {
                        position: [r * a.cos(), r * a.sin()],
                        force: Some([force, -force]),
                        shape,
                    }
                })
                .collect();
            let curls: Vec<_> = (0..cap.curls)
                .map(|i| CurlConstraint {
                    position: [0.05 * i as f64, 0.9],
                    curl: force,
                    shape: PartShape::Point,
                })
                .collect();
            let bounds: Vec<f64> = (0..cap.centers).map(|j| if j % 2 == 0 { 1.0 } else { 0.5 }).collect();
            let problem = Problem {
                mu_m_g: 1.0,
                k_max: 1.0,
                centers: &centers,
                parts: &parts,
                curls: &curls,
                k_bounds: &bounds,
            };
            ok &= self.solve(&problem, &mut out).is_ok();
        }
        self.forget_warm_start();
        ok
    }

    /// The system of the last successful assembly (the last solve, unless
    /// its input was rejected first), its columns scaled by per-center
    /// bounds if the problem had unequal ones (module doc).
    pub fn last_system(&self) -> LeastSquaresSystem<'_> {
        let (m, n) = self.last_shape;
        LeastSquaresSystem {
            rows: &self.rows[..m * n],
            b: &self.b[..m],
            m,
            n,
            eps: system::tikhonov_eps(&self.rows[..m * n], n.max(1), self.params.tikhonov),
        }
    }

    /// The next solve starts cold (benchmarks; a new scene).
    pub fn forget_warm_start(&mut self) {
        self.warm.valid = false;
        self.sparse.forget();
    }

    /// A [`Solution`] with enough room for any problem this solver accepts.
    pub fn new_solution(&self) -> Solution {
        Solution::with_capacity(self.cap)
    }

    /// QR of the assembled A (pivoted or not), its exact minimum-norm K in
    /// `exact_k`, and the κ₂ estimate (∞ when the rank is short).
    fn factor_and_estimate(&mut self, m: usize, n: usize, pivot: bool) -> (min_norm::QrSummary, f64) {
        let summary = min_norm::min_norm_solve(
            &self.rows,
            &self.b,
            m,
            n,
            min_norm::QrOptions { rank_tolerance: self.params.rank_tolerance, pivot },
            &mut self.qr,
            &mut self.exact_k,
        );
        let condition = if summary.rank < summary.dim {
            f64::INFINITY
        } else {
            condition::condition_estimate(
                min_norm::r_factor(&self.qr, summary),
                self.params.condition_iterations,
                self.params.condition_tolerance,
                condition::ConditionScratch {
                    v: &mut self.cond_v,
                    w: &mut self.cond_w,
                    u: &mut self.cond_u,
                    inv_diag: &mut self.cond_diag,
                },
            )
        };
        (summary, condition)
    }

    /// Steps 2–4 of the module doc.
    fn cold_solve(&mut self, problem: &Problem<'_>, m: usize, n: usize, out: &mut Solution) {
        // QR without pivoting first: it is cheaper and exact whenever A is
        // well conditioned. Only a short rank or a κ over the gate pays for
        // the rank-revealing, pivoted factorisation, which then reports the
        // rank. Both κ estimates are lower bounds on the same κ₂ (and a tiny
        // unpivoted |r_ii| bounds σ_min too), so the larger one stands: the
        // redo can never reopen the exact path.
        let (mut summary, mut condition) = self.factor_and_estimate(m, n, false);
        if summary.rank < summary.dim || condition > self.params.max_condition {
            let first = condition;
            (summary, condition) = self.factor_and_estimate(m, n, true);
            condition = condition.max(first);
        }
        out.rank = summary.rank;
        out.condition = condition;
        let full_rank = summary.rank == summary.dim;
        let exact_ok = full_rank
            && out.condition <= self.params.max_condition
            && self.exact_k[..n].iter().all(|k| k.abs() <= problem.k_max);
        if exact_ok {
            out.k.copy_from_slice(&self.exact_k[..n]);
            out.method = SolveMethod::Exact;
            self.warm.valid = false;
            return;
        }
        // Guess the active set from the exact K clipped into the box (even
        // over the κ gate it is the better guess); with a short rank its
        // values are meaningless: start all free, the first iteration is
        // then the regularised optimum.
        let state = &mut self.bounded.state[..n];
        for (s, &k) in state.iter_mut().zip(&self.exact_k[..n]) {
            *s = if full_rank && k.abs() > problem.k_max { if k > 0.0 { 1 } else { -1 } } else { 0 };
        }
        self.run_bounded(problem, m, n, out);
    }

    /// The warm-started bounded solve, from the active set the last one left
    /// in `self.bounded.state`; false (and nothing to use) when it ended
    /// with no bound active or did not converge.
    fn warm_solve(&mut self, problem: &Problem<'_>, m: usize, n: usize, out: &mut Solution) -> bool {
        self.run_bounded(problem, m, n, out);
        if !self.warm.valid {
            return false;
        }
        out.rank = 0;
        out.condition = 0.0;
        out.warm_started = true;
        true
    }

    /// Bounded solve from the guess in `self.bounded.state`, which then holds
    /// its active set; marks it usable by the next frame when it converged
    /// with a bound active.
    fn run_bounded(&mut self, problem: &Problem<'_>, m: usize, n: usize, out: &mut Solution) {
        let input = BoundedInput {
            rows: &self.rows,
            b: &self.b,
            m,
            n,
            k_max: problem.k_max,
            tikhonov: self.params.tikhonov,
            max_iterations: self.params.bounded_max_iterations,
        };
        let report = bounded::bounded_solve(&input, &mut self.bounded, &mut out.k);
        out.iterations += report.iterations;
        out.converged = report.converged;
        out.method = SolveMethod::BoundedLeastSquares;
        let warm = &mut self.warm;
        warm.valid = report.converged && report.active > 0;
        if warm.valid {
            warm.rows = m;
            warm.force_rows = problem.force_rows();
            warm.centers.clear();
            warm.centers.extend_from_slice(problem.centers);
        }
    }

    /// The sparse path (`sparse.rs`): weights over the candidate centers,
    /// then `slots` slots apportioned to them.
    fn sparse_solve(&mut self, problem: &Problem<'_>, m: usize, n: usize, slots: usize, out: &mut Solution) {
        // The assembled b is scaled by n/μmg; the weights answer 1/μmg.
        for b in &mut self.b[..m] {
            *b /= n as f64;
        }
        let input = sparse::SparseInput {
            rows: &self.rows,
            b: &self.b,
            m,
            n,
            k_max: problem.k_max,
            max_iterations: self.params.sparse_iterations,
            min_dist: &self.min_dist,
            keep_out: self.params.sparse_keep_out,
            shrink: self.params.sparse_shrink,
        };
        let report = sparse::sparse_solve(&input, &mut self.sparse);
        for b in &mut self.b[..m] {
            *b *= n as f64;
        }
        let w = sparse::weights(&self.sparse, n);
        sparse::apportion(w, slots, problem.k_max, &mut out.counts, &mut out.k, &mut self.remainder);
        // The counts fixed, the k of the played centers by bounded least
        // squares on their columns, each scaled by its share c_j·n/N of the
        // cycle (the assembled b is in units of n/μmg).
        self.played.clear();
        self.played.extend((0..n).filter(|&j| out.counts[j] > 0).map(|j| j as u16));
        let s = self.played.len();
        for (t, &j) in self.played.iter().enumerate() {
            let j = usize::from(j);
            let scale = f64::from(out.counts[j]) * n as f64 / slots as f64;
            for i in 0..m {
                self.compact[i * s + t] = self.rows[i * n + j] * scale;
            }
        }
        self.bounded.state[..s].fill(0);
        let bounded_input = BoundedInput {
            rows: &self.compact,
            b: &self.b,
            m,
            n: s,
            k_max: problem.k_max,
            tikhonov: self.params.tikhonov,
            max_iterations: self.params.bounded_max_iterations,
        };
        let polish = bounded::bounded_solve(&bounded_input, &mut self.bounded, &mut self.exact_k);
        for (&j, &k) in self.played.iter().zip(&self.exact_k[..s]) {
            out.k[usize::from(j)] = k;
        }
        out.method = SolveMethod::Sparse;
        out.rank = 0;
        out.condition = 0.0;
        out.iterations = report.iterations + polish.iterations;
        out.converged = polish.converged;
        out.budget_active = report.budget_active;
        self.warm.valid = false;
    }

    /// Fill `column_scale` with s_j = u_j / u_max and scale A's columns by
    /// it where it is not 1; returns u_max and whether any column was.
    fn scale_columns(&mut self, problem: &Problem<'_>, m: usize, n: usize) -> (f64, bool) {
        let bound = |j: usize| problem.k_bounds.get(j).map_or(problem.k_max, |&u| u.min(problem.k_max));
        let top = (0..n).map(bound).fold(0.0, f64::max);
        for j in 0..n {
            self.column_scale[j] = bound(j) / top;
        }
        let scaled = self.column_scale[..n].iter().any(|&s| s != 1.0);
        if scaled {
            for row in self.rows[..m * n].chunks_exact_mut(n) {
                for (a, s) in row.iter_mut().zip(&self.column_scale[..n]) {
                    *a *= s;
                }
            }
        }
        (top, scaled)
    }

    /// Solve one problem into `out` (which must come from
    /// [`Solver::new_solution`] or have at least the same capacity).
    pub fn solve(&mut self, problem: &Problem<'_>, out: &mut Solution) -> Result<(), SolveError> {
        validate::validate_problem(problem, &self.cap, &self.params)?;
        let n = problem.centers.len();
        let m = assemble::assemble(
            problem,
            &mut self.rows,
            &mut self.b,
            &mut self.min_dist,
            &mut self.center_x,
            &mut self.center_y,
        )?;
        self.last_shape = (m, n);
        let (k_top, scaled) = self.scale_columns(problem, m, n);
        // Every path below solves in the scaled variables under one bound.
        let problem = &Problem { k_max: k_top, ..*problem };

        out.k.clear();
        out.k.resize(n, 0.0);
        out.counts.clear();
        out.counts.resize(n, 1);
        out.iterations = 0;
        out.converged = true;
        out.warm_started = false;
        out.saturated = false;
        out.budget_active = false;
        let slots = self.params.cycle_slots;
        if slots > 0 {
            self.sparse_solve(problem, m, n, slots, out);
        } else if m == 0 {
            out.method = SolveMethod::Trivial;
            out.rank = 0;
            out.condition = 1.0;
        } else if !(self.params.warm_start
            && self.warm.matches(problem, m)
            && self.warm_solve(problem, m, n, out))
        {
            self.cold_solve(problem, m, n, out);
        }
        // A bound counts as active within a relative 1e-9 of k_max (the
        // scaled k: every center's own bound).
        out.at_bound = out.k.iter().filter(|k| k.abs() >= problem.k_max * (1.0 - 1e-9)).count();

        // The cycle's weights w_j = c_j·k_j / N times n, in the units of the
        // assembled b (N/μmg per unit force with N = n): in the paper's
        // cycle, k itself.
        let weights: &[f64] = if slots > 0 {
            let cycle = slots as f64;
            for (j, w) in self.exact_k[..n].iter_mut().enumerate() {
                *w = f64::from(out.counts[j]) * out.k[j] * n as f64 / cycle;
            }
            &self.exact_k[..n]
        } else {
            &out.k
        };
        bounded::mat_vec(&self.rows, m, n, weights, &mut self.residual);
        let r2: f64 = self.residual[..m].iter().zip(&self.b[..m]).map(|(ak, b)| (ak - b) * (ak - b)).sum();
        out.residual = r2.sqrt() * problem.mu_m_g / n as f64;
        let b2: f64 = self.b[..m].iter().map(|b| b * b).sum();
        let request = b2.sqrt() * problem.mu_m_g / n as f64;
        out.saturated = (out.at_bound > 0 || out.budget_active)
            && out.residual > SATURATION_TOLERANCE * request + SATURATION_FLOOR;
        if scaled {
            for j in 0..n {
                out.k[j] *= self.column_scale[j];
                self.exact_k[j] *= self.column_scale[j];
            }
        }
        let weights: &[f64] = if slots > 0 { &self.exact_k[..n] } else { &out.k };

        // Achieved forces and curls: the model's A·w (already in `residual`,
        // in units scaled by n/μmg) for constrained rows; the field sum for
        // parts whose force is free (they have no row).
        let unscale = problem.mu_m_g / n as f64;
        let mf = problem.force_rows();
        out.achieved_forces.clear();
        let mut i = 0;
        for p in problem.parts {
            if p.force.is_some() {
                out.achieved_forces.push([self.residual[i] * unscale, self.residual[mf + i] * unscale]);
                i += 1;
            } else if p.shape == PartShape::Point {
                out.achieved_forces.push(field::cycle_force(
                    weights,
                    problem.centers,
                    problem.mu_m_g,
                    p.position,
                ));
            } else {
                let mut f = [0.0; 2];
                shape::for_each_wrench_row(&p.shape, p.position, problem.centers, |j, t, _| {
                    let w = weights.get(j).copied().unwrap_or(0.0);
                    f[0] += w * t[0];
                    f[1] += w * t[1];
                });
                out.achieved_forces.push([f[0] * unscale, f[1] * unscale]);
            }
        }
        out.achieved_curls.clear();
        out.achieved_curls.extend(self.residual[2 * mf..m].iter().map(|r| r * unscale));
        order::play_order(&out.k, &self.min_dist, &mut out.priority, &mut out.order);
        let counts = &out.counts;
        out.order.retain(|&j| counts[usize::from(j)] > 0);
        Ok(())
    }
}
