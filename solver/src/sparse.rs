//! Sparse slot allocation (`SolverParams::cycle_slots` > 0): the configured
//! centers are *candidates*, and a cycle of a fixed number of slots plays
//! only the few that the request needs, each as often as it needs.
//!
//! A cycle of N slots where center j fills c_j slots with intensity k_j
//! gives every point the force μmg Σ_j w_j φ_j with w_j = c_j k_j / N, and
//! Σ|w_j| ≤ k_max. So the forces a cycle can give are exactly A·w over the
//! ℓ1 ball ‖w‖₁ ≤ k_max, which holds the paper's box |k_j| ≤ k_max (one
//! slot per center, w_j = k_j / n) many times over: a strong slot near a
//! part is not diluted by n − 1 others.
//!
//! **Algorithm.** 1. *Which centers, how often:* min ½‖A w − b‖² + λ‖w‖₁
//! subject to ‖w‖₁ ≤ k_max, by accelerated proximal gradient (FISTA): soft
//! thresholding by λ (small, relative to ‖Aᵀb‖∞, so that w stays on few
//! centers even when the budget does not bind), then projection onto the
//! ℓ1 ball by sorting |w| (Duchi et al. 2008); step 1/L with L ≥ ‖A‖₂²
//! from a fixed number of power iterations. Centers closer than a
//! keep-out to a constrained point are never used. It starts from the last
//! frame's w (consecutive frames ask nearly the same question) and stops
//! after `sparse_iterations` iterations or once a step moves no weight by
//! more than 1e-12. The N slots then go to the centers by largest
//! remainder of N·|w_j| / ‖w‖₁ (ties to the lower index); a center whose
//! share rounds to no slot is not played.
//! 2. *How strongly:* with the counts c_j fixed, the k_j of the played
//! centers are the bounded least-squares optimum (`bounded.rs`, |k_j| ≤
//! k_max) of A·(c k / N) = b, so neither the ℓ1 weight's bias nor the
//! rounding is left in the answer.
//!
//! **Cost:** (power iterations + iterations) × 2·m·n flops, plus one
//! bounded solve on at most N columns, no allocation; 20 × 96 at 300
//! iterations ≈ 1.2 Mflop. **Guarantees:** every |k_j| ≤
//! k_max, exactly N slots, bit-identical for the same inputs and the same
//! previous frame. The optimum is approached, not certified: the reported
//! residual and achieved forces are those of the apportioned slots, so
//! rounding and early stopping show there, never silently.

// `!(x > 0.0)` deliberately takes NaN as "not positive".
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::dense::dot;

/// Power iterations for the step size; the estimate is a lower bound on
/// ‖A‖₂², so it is raised by `STEP_MARGIN`.
const POWER_ITERATIONS: usize = 30;
const STEP_MARGIN: f64 = 1.1;

#[derive(Debug)]
pub(crate) struct SparseBuffers {
    /// The current weights w (kept across frames: the warm start).
    w: Vec<f64>,
    previous: Vec<f64>,
    point: Vec<f64>,
    gradient: Vec<f64>,
    residual: Vec<f64>,
    sorted: Vec<f64>,
    /// Number of centers `w` belongs to (0: no warm start).
    warm_n: usize,
}

/// What one sparse solve found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SparseReport {
    pub iterations: usize,
    /// ‖w‖₁ reached k_max: the request asks more than one cycle can give.
    pub budget_active: bool,
}

impl SparseBuffers {
    pub(crate) fn new(m: usize, n: usize) -> Self {
        Self {
            w: vec![0.0; n],
            previous: vec![0.0; n],
            point: vec![0.0; n],
            gradient: vec![0.0; n],
            residual: vec![0.0; m],
            sorted: vec![0.0; n],
            warm_n: 0,
        }
    }

    pub(crate) fn forget(&mut self) {
        self.warm_n = 0;
    }
}

/// `out` = Aᵀ·v for row-major A (m × n).
fn mat_t_vec(rows: &[f64], m: usize, n: usize, v: &[f64], out: &mut [f64]) {
    out[..n].fill(0.0);
    for i in 0..m {
        let vi = v[i];
        for (o, a) in out[..n].iter_mut().zip(&rows[i * n..(i + 1) * n]) {
            *o += a * vi;
        }
    }
}

/// ‖A‖₂² estimated by power iteration on AᵀA from a fixed start.
fn spectral_norm_sq(
    rows: &[f64],
    m: usize,
    n: usize,
    v: &mut [f64],
    av: &mut [f64],
    atav: &mut [f64],
) -> f64 {
    v[..n].fill(1.0 / (n as f64).sqrt());
    let mut estimate = 0.0;
    for _ in 0..POWER_ITERATIONS {
        for i in 0..m {
            av[i] = dot(&rows[i * n..(i + 1) * n], &v[..n]);
        }
        mat_t_vec(rows, m, n, av, atav);
        let norm = dot(&atav[..n], &atav[..n]).sqrt();
        if !(norm > 0.0) {
            return estimate;
        }
        estimate = norm;
        for (x, y) in v[..n].iter_mut().zip(&atav[..n]) {
            *x = y / norm;
        }
    }
    estimate
}

/// Project `v` onto {‖v‖₁ ≤ radius} in place; `sorted` is scratch (n).
fn project_l1(v: &mut [f64], radius: f64, sorted: &mut [f64]) -> bool {
    let total: f64 = v.iter().map(|x| x.abs()).sum();
    if total <= radius {
        return false;
    }
    let sorted = &mut sorted[..v.len()];
    for (s, x) in sorted.iter_mut().zip(v.iter()) {
        *s = x.abs();
    }
    sorted.sort_unstable_by(|a, b| b.total_cmp(a));
    let (mut cumulative, mut theta) = (0.0, 0.0);
    for (i, &u) in sorted.iter().enumerate() {
        cumulative += u;
        let t = (cumulative - radius) / (i + 1) as f64;
        if u > t {
            theta = t;
        }
    }
    for x in v.iter_mut() {
        *x = x.signum() * (x.abs() - theta).max(0.0);
    }
    true
}

/// The sparse problem: row-major A (m × n), b, and which centers may play.
pub(crate) struct SparseInput<'a> {
    pub rows: &'a [f64],
    pub b: &'a [f64],
    pub m: usize,
    pub n: usize,
    pub k_max: f64,
    pub max_iterations: usize,
    /// Distance from each center to its nearest constrained point ...
    pub min_dist: &'a [f64],
    /// ... below which the center is not played.
    pub keep_out: f64,
    /// ℓ1 weight relative to ‖Aᵀb‖∞ (which would zero every weight): keeps
    /// the weights on few centers when the budget does not bind.
    pub shrink: f64,
}

/// min ½‖A w − b‖² s.t. ‖w‖₁ ≤ k_max, w_j = 0 for the centers within
/// `keep_out` of a constrained point; the weights are left in the buffers
/// (`weights`).
pub(crate) fn sparse_solve(input: &SparseInput<'_>, buf: &mut SparseBuffers) -> SparseReport {
    let SparseInput { rows, b, m, n, k_max, max_iterations, min_dist, keep_out, shrink } = *input;
    let SparseBuffers { w, previous, point, gradient, residual, sorted, warm_n } = buf;
    if *warm_n != n {
        w[..n].fill(0.0);
    }
    *warm_n = n;
    let barred = |j: usize| min_dist[j] < keep_out;
    let lipschitz = STEP_MARGIN * spectral_norm_sq(rows, m, n, point, residual, gradient);
    if !(lipschitz > 0.0) {
        w[..n].fill(0.0);
        return SparseReport { iterations: 0, budget_active: false };
    }
    let step = 1.0 / lipschitz;
    mat_t_vec(rows, m, n, b, gradient);
    let threshold = step * shrink * gradient[..n].iter().fold(0.0f64, |a, g| a.max(g.abs()));
    for j in (0..n).filter(|&j| barred(j)) {
        w[j] = 0.0;
    }
    project_l1(&mut w[..n], k_max, sorted);
    previous[..n].copy_from_slice(&w[..n]);
    point[..n].copy_from_slice(&w[..n]);
    let mut t = 1.0f64;
    let mut iterations = 0;
    while iterations < max_iterations {
        iterations += 1;
        for i in 0..m {
            residual[i] = dot(&rows[i * n..(i + 1) * n], &point[..n]) - b[i];
        }
        mat_t_vec(rows, m, n, residual, gradient);
        for j in 0..n {
            let v = point[j] - step * gradient[j];
            w[j] = if barred(j) { 0.0 } else { v.signum() * (v.abs() - threshold).max(0.0) };
        }
        project_l1(&mut w[..n], k_max, sorted);
        let t_next = 0.5 * (1.0 + (1.0 + 4.0 * t * t).sqrt());
        let momentum = (t - 1.0) / t_next;
        let mut moved = 0.0f64;
        for j in 0..n {
            let dw = w[j] - previous[j];
            moved = moved.max(dw.abs());
            point[j] = w[j] + momentum * dw;
            previous[j] = w[j];
        }
        t = t_next;
        if moved <= 1e-12 {
            break;
        }
    }
    let total: f64 = w[..n].iter().map(|x| x.abs()).sum();
    SparseReport { iterations, budget_active: total >= k_max * (1.0 - 1e-6) }
}

/// The weights of the last [`sparse_solve`].
pub(crate) fn weights(buf: &SparseBuffers, n: usize) -> &[f64] {
    &buf.w[..n]
}

/// Apportion `slots` slots to the weights `w` (largest remainder of
/// slots·|w_j|/‖w‖₁, ties to the lower index): `counts[j]` slots of
/// intensity `k[j]` = slots·w_j / counts[j], clipped to ±k_max. All-zero
/// weights give every slot to center 0 with k = 0 (the plate still runs a
/// closed, forceless cycle). `remainder` is scratch (n).
pub(crate) fn apportion(
    w: &[f64],
    slots: usize,
    k_max: f64,
    counts: &mut [u16],
    k: &mut [f64],
    remainder: &mut [f64],
) {
    let n = w.len();
    let (counts, k, remainder) = (&mut counts[..n], &mut k[..n], &mut remainder[..n]);
    counts.fill(0);
    k.fill(0.0);
    let total: f64 = w.iter().map(|x| x.abs()).sum();
    if !(total > 0.0) || n == 0 {
        if let Some(c) = counts.first_mut() {
            *c = slots as u16;
        }
        return;
    }
    let mut given = 0usize;
    for j in 0..n {
        let quota = slots as f64 * w[j].abs() / total;
        let whole = quota.floor();
        counts[j] = whole as u16;
        remainder[j] = if w[j] != 0.0 { quota - whole } else { f64::NEG_INFINITY };
        given += whole as usize;
    }
    while given < slots {
        let mut best = 0;
        for j in 1..n {
            if remainder[j] > remainder[best] {
                best = j;
            }
        }
        counts[best] += 1;
        remainder[best] = f64::NEG_INFINITY;
        given += 1;
    }
    for j in 0..n {
        if counts[j] > 0 {
            k[j] = (slots as f64 * w[j] / f64::from(counts[j])).clamp(-k_max, k_max);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_lands_on_the_l1_ball_and_keeps_signs() {
        let mut v = [3.0, -1.0, 0.5, 0.0];
        let mut s = [0.0; 4];
        assert!(project_l1(&mut v, 2.0, &mut s));
        let total: f64 = v.iter().map(|x| x.abs()).sum();
        assert!((total - 2.0).abs() < 1e-12, "{v:?}");
        // θ = 1: (3 − 1) + (1 − 1) → [2, 0, 0, 0].
        assert_eq!(v, [2.0, 0.0, 0.0, 0.0]);
        let mut inside = [0.1, -0.2];
        assert!(!project_l1(&mut inside, 1.0, &mut s));
        assert_eq!(inside, [0.1, -0.2]);
    }

    #[test]
    fn apportioning_fills_every_slot_within_k_max() {
        let w = [0.3, -0.15, 0.0, 0.05];
        let (mut c, mut k, mut r) = ([0u16; 4], [0.0; 4], [0.0; 4]);
        apportion(&w, 24, 0.5, &mut c, &mut k, &mut r);
        assert_eq!(c.iter().map(|&x| usize::from(x)).sum::<usize>(), 24);
        assert_eq!(c, [14, 7, 0, 3]);
        assert!(k.iter().all(|k| k.abs() <= 0.5));
        assert!(k[0] > 0.0 && k[1] < 0.0 && k[2] == 0.0 && k[3] > 0.0);
        // c_j k_j / N equals w_j where nothing was clipped; rounding 7.2
        // slots down to 7 would need |k_1| = 0.514: clipped to k_max.
        assert!((f64::from(c[3]) * k[3] / 24.0 - w[3]).abs() < 1e-12);
        assert_eq!(k[1], -0.5);
        apportion(&[0.0; 4], 8, 0.5, &mut c, &mut k, &mut r);
        assert_eq!((c, k), ([8, 0, 0, 0], [0.0; 4]));
    }

    #[test]
    fn a_consistent_small_request_is_met() {
        // Two columns, one row: b = 0.2 is reachable with ‖w‖₁ ≤ 0.8.
        let input = |b: &'static [f64], min_dist: &'static [f64]| SparseInput {
            rows: &[1.0, 0.5],
            b,
            m: 1,
            n: 2,
            k_max: 0.8,
            max_iterations: 500,
            min_dist,
            keep_out: 0.1,
            shrink: 0.0,
        };
        let mut buf = SparseBuffers::new(1, 2);
        let r = sparse_solve(&input(&[0.2], &[1.0, 1.0]), &mut buf);
        let w = weights(&buf, 2);
        assert!((w[0] + 0.5 * w[1] - 0.2).abs() < 1e-9, "{w:?}");
        assert!(!r.budget_active);
        // Beyond the budget: the best is all weight on the stronger column.
        buf.forget();
        let r = sparse_solve(&input(&[2.0], &[1.0, 1.0]), &mut buf);
        let w = weights(&buf, 2);
        assert!(r.budget_active);
        assert!((w[0] - 0.8).abs() < 1e-9 && w[1].abs() < 1e-9, "{w:?}");
        // The stronger center sits on a point: only the other may play.
        buf.forget();
        let r = sparse_solve(&input(&[2.0], &[0.05, 1.0]), &mut buf);
        let w = weights(&buf, 2);
        assert!(r.budget_active);
        assert!(w[0] == 0.0 && (w[1] - 0.8).abs() < 1e-9, "{w:?}");
    }
}
