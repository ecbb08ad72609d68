//! The largest force one point part can be given: what a planner may ask
//! and still be answered in full (docs/protocol.md, `RigInfo`).
//!
//! With e_j = (P − C_j)/|P − C_j|, t_j = R90 e_j and u_j the bound of
//! center j, the forces one cycle can give a lone part at P (curl free)
//! form a convex set Z:
//! - the paper's cycle (one slot per center, N = n): Z = {(μmg/n) Σ_j k_j
//!   t_j : |k_j| ≤ u_j}, a zonotope whose edges run along the t_k, so its
//!   facet normals are the e_k and its extent along a unit e is h(e) =
//!   (μmg/n) Σ_j u_j |e·t_j|;
//! - a sparse cycle of N slots: (μmg/N) Σ_j c_j k_j t_j with Σ c_j = N (the
//!   solver scales column j by its share c_j·n/N), so Z = μmg·conv{±u_j t_j}
//!   over the centers at least the keep-out away from P.
//!
//! The largest force along a unit d is the ray's exit from Z: on the
//! paper's cycle min over k (e_k·d ≠ 0) of h(e_k)/|e_k·d|; on a sparse one
//! the farthest crossing of the ray with a chord between two of the ±u_j
//! t_j. The largest in any direction is Z's farthest vertex. Start-up and
//! test code: it allocates.

use super::field::unit_tangent;

/// Where on the plate a lone part can be pushed hardest, and how hard.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaxForce {
    /// N.
    pub force: f64,
    /// The position (m) and the unit direction of that force.
    pub at: [f64; 2],
    pub direction: [f64; 2],
}

/// The cycle a bound is asked for: `slots` = 0 is the paper's cycle; N > 0
/// a sparse one that plays no center within `keep_out` (m) of the part.
#[derive(Debug, Clone, Copy)]
struct Cycle<'a> {
    centers: &'a [[f64; 2]],
    bounds: &'a [f64],
    mu_m_g: f64,
    slots: usize,
    keep_out: f64,
}

impl Cycle<'_> {
    /// Center j's unit tangent at `p` and its bound, for the centers that
    /// may push a part there (none closer than 1e-9 m: the direction is
    /// undefined on the center itself).
    fn tangents(&self, p: [f64; 2]) -> impl Iterator<Item = ([f64; 2], f64)> + '_ {
        let near = if self.slots > 0 { self.keep_out } else { 1e-9 };
        self.centers.iter().zip(self.bounds).filter_map(move |(&c, &u)| {
            let (t, r) = unit_tangent(p, c);
            (r >= near && r.is_finite()).then_some((t, u))
        })
    }

    /// How far the ray along the unit `d` reaches in Z (module doc).
    fn along(&self, p: [f64; 2], d: [f64; 2]) -> f64 {
        let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
        let dot = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
        let terms: Vec<([f64; 2], f64)> = self.tangents(p).collect();
        if self.slots > 0 {
            // The generators ±u_j t_j; every chord between two of them.
            let q: Vec<[f64; 2]> =
                terms.iter().flat_map(|&(t, u)| [[u * t[0], u * t[1]], [-u * t[0], -u * t[1]]]).collect();
            let mut best: f64 = 0.0;
            for (a, &qa) in q.iter().enumerate() {
                let n = qa[0].hypot(qa[1]);
                if cross(d, qa).abs() <= 1e-12 * n && dot(d, qa) > 0.0 {
                    best = best.max(n);
                }
                for &qb in &q[a + 1..] {
                    let edge = [qb[0] - qa[0], qb[1] - qa[1]];
                    let den = cross(d, edge);
                    if den == 0.0 {
                        continue;
                    }
                    let (s, lambda) = (cross(qa, qb) / den, -cross(d, qa) / den);
                    if (0.0..=1.0).contains(&lambda) && s > best {
                        best = s;
                    }
                }
            }
            self.mu_m_g * best
        } else {
            // The facet normals are the radial directions e_k = −R90 t_k.
            let n = self.centers.len().max(1) as f64;
            let mut best = f64::INFINITY;
            for &(tk, _) in &terms {
                let e = [tk[1], -tk[0]];
                let across = dot(e, d).abs();
                if across > 1e-12 {
                    let h: f64 = terms.iter().map(|&(t, u)| u * dot(e, t).abs()).sum();
                    best = best.min(h / across);
                }
            }
            if best.is_infinite() {
                // Every tangent along d (one center, or all aligned).
                best = terms.iter().map(|&(t, u)| u * dot(d, t).abs()).sum();
            }
            self.mu_m_g / n * best
        }
    }

    /// The largest force at `p` in any direction, and that direction.
    fn best_at(&self, p: [f64; 2]) -> (f64, [f64; 2]) {
        if self.slots > 0 {
            // One center takes every slot: the strongest along its tangent.
            return self.tangents(p).fold((0.0, [1.0, 0.0]), |best, (t, u)| {
                if self.mu_m_g * u > best.0 { (self.mu_m_g * u, t) } else { best }
            });
        }
        // The reachable set is a zonotope; its farthest vertex is the sum
        // Σ s_j u_j t_j for the signs s_j = sign(d·t_j) of some direction d.
        // The signs change only where d ⟂ t_j, so one d inside each arc
        // between those angles is enough: 2n candidates, sorted.
        let terms: Vec<([f64; 2], f64)> = self.tangents(p).collect();
        let mut cuts: Vec<f64> = terms
            .iter()
            .flat_map(|(t, _)| {
                let a = t[1].atan2(t[0]) + core::f64::consts::FRAC_PI_2;
                [
                    a.rem_euclid(core::f64::consts::TAU),
                    (a + core::f64::consts::PI).rem_euclid(core::f64::consts::TAU),
                ]
            })
            .collect();
        cuts.sort_by(f64::total_cmp);
        let n = self.centers.len().max(1) as f64;
        let mut best = (0.0, [1.0, 0.0]);
        for (i, &a) in cuts.iter().enumerate() {
            let b = cuts.get(i + 1).copied().unwrap_or(cuts[0] + core::f64::consts::TAU);
            let mid = 0.5 * (a + b);
            let d = [mid.cos(), mid.sin()];
            let mut v = [0.0; 2];
            for (t, u) in &terms {
                let s = if d[0] * t[0] + d[1] * t[1] >= 0.0 { *u } else { -*u };
                v[0] += s * t[0];
                v[1] += s * t[1];
            }
            let norm = v[0].hypot(v[1]);
            let force = self.mu_m_g / n * norm;
            if force > best.0 && norm > 0.0 {
                best = (force, [v[0] / norm, v[1] / norm]);
            }
        }
        best
    }
}

/// The largest force (N) a lone point part at `p` can be given along the
/// unit direction `d` (curl free) by a cycle over `centers` with per-center
/// bounds `bounds` (module doc; `slots` = 0: the paper's cycle).
pub fn max_force_in(
    centers: &[[f64; 2]],
    bounds: &[f64],
    mu_m_g: f64,
    slots: usize,
    keep_out: f64,
    p: [f64; 2],
    d: [f64; 2],
) -> f64 {
    Cycle { centers, bounds, mu_m_g, slots, keep_out }.along(p, d)
}

/// The largest force (N) in any direction at `p`, and its unit direction.
pub fn max_force_at(
    centers: &[[f64; 2]],
    bounds: &[f64],
    mu_m_g: f64,
    slots: usize,
    keep_out: f64,
    p: [f64; 2],
) -> (f64, [f64; 2]) {
    Cycle { centers, bounds, mu_m_g, slots, keep_out }.best_at(p)
}

/// Grid points per axis of the search, before refinement.
const GRID: usize = 41;

/// Places closer than this to a center are left out of the search (m): a
/// part there is refused (on the center) or pushed every which way.
pub const CENTER_CLEARANCE: f64 = 1e-3;

/// The largest force a lone point part can be given anywhere on the plate
/// |x| ≤ half_extent[0], |y| ≤ half_extent[1], at least
/// [`CENTER_CLEARANCE`] from every center: the best of a 41 × 41 grid,
/// then a pattern search from the best few points down to 1e-9 of the
/// plate's size. A lower bound on the true supremum, attained at `at`.
pub fn max_force_on_plate(
    centers: &[[f64; 2]],
    bounds: &[f64],
    mu_m_g: f64,
    slots: usize,
    keep_out: f64,
    half_extent: [f64; 2],
) -> MaxForce {
    let cycle = Cycle { centers, bounds, mu_m_g, slots, keep_out };
    let clear = |p: [f64; 2]| centers.iter().all(|c| (p[0] - c[0]).hypot(p[1] - c[1]) >= CENTER_CLEARANCE);
    let value = |p: [f64; 2]| if clear(p) { cycle.best_at(p).0 } else { f64::NEG_INFINITY };
    let [hx, hy] = half_extent;
    let clamp = |p: [f64; 2]| [p[0].clamp(-hx, hx), p[1].clamp(-hy, hy)];
    let mut grid: Vec<(f64, [f64; 2])> = Vec::with_capacity(GRID * GRID);
    for i in 0..GRID {
        for j in 0..GRID {
            let s = |k: usize, h: f64| -h + 2.0 * h * k as f64 / (GRID - 1) as f64;
            let p = [s(i, hx), s(j, hy)];
            grid.push((value(p), p));
        }
    }
    grid.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut best = MaxForce { force: 0.0, at: [0.0; 2], direction: [1.0, 0.0] };
    for &(_, start) in grid.iter().take(8) {
        let (mut f, mut p) = (value(start), start);
        let mut step = [2.0 * hx / (GRID - 1) as f64, 2.0 * hy / (GRID - 1) as f64];
        while step[0].max(step[1]) > 1e-9 * hx.max(hy) {
            let mut moved = false;
            for (dx, dy) in [
                (1.0, 0.0),
                (-1.0, 0.0),
                (0.0, 1.0),
                (0.0, -1.0),
                (1.0, 1.0),
                (-1.0, -1.0),
                (1.0, -1.0),
                (-1.0, 1.0),
            ] {
                let q = clamp([p[0] + dx * step[0], p[1] + dy * step[1]]);
                let g = value(q);
                if g > f {
                    (f, p, moved) = (g, q, true);
                }
            }
            if !moved {
                step = [step[0] / 2.0, step[1] / 2.0];
            }
        }
        if f > best.force {
            let (force, direction) = cycle.best_at(p);
            best = MaxForce { force, at: p, direction };
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_center_gives_its_bound_along_its_tangent_only() {
        let (f, d) = max_force_at(&[[0.0, 0.0]], &[0.5], 0.1, 0, 0.0, [1.0, 0.0]);
        assert!((f - 0.05).abs() < 1e-15 && (d[0].abs() < 1e-12) && (d[1].abs() - 1.0).abs() < 1e-12);
        assert!(
            (max_force_in(&[[0.0, 0.0]], &[0.5], 0.1, 0, 0.0, [1.0, 0.0], [0.0, -1.0]) - 0.05).abs() < 1e-15
        );
        assert_eq!(max_force_in(&[[0.0, 0.0]], &[0.5], 0.1, 0, 0.0, [1.0, 0.0], [0.6, 0.8]), 0.0);
    }

    /// Z by brute force: the farthest s·d a dense sample of K reaches.
    fn reach_by_sampling(centers: &[[f64; 2]], bounds: &[f64], p: [f64; 2], d: [f64; 2]) -> f64 {
        // On the boundary of a zonotope along d some k_j are at ±u_j and at
        // most one is free: try every sign pattern and free center.
        let n = centers.len();
        let t: Vec<[f64; 2]> = centers.iter().map(|&c| unit_tangent(p, c).0).collect();
        let mut best: f64 = 0.0;
        for signs in 0..1u32 << n {
            for free in 0..n {
                let mut v = [0.0; 2];
                for j in (0..n).filter(|&j| j != free) {
                    let s = if signs >> j & 1 == 1 { bounds[j] } else { -bounds[j] };
                    v = [v[0] + s * t[j][0], v[1] + s * t[j][1]];
                }
                // v + k t_free ∥ d: k from the cross product.
                let den = t[free][0] * d[1] - t[free][1] * d[0];
                if den.abs() < 1e-15 {
                    continue;
                }
                let k = -(v[0] * d[1] - v[1] * d[0]) / den;
                if k.abs() <= bounds[free] {
                    let w = [v[0] + k * t[free][0], v[1] + k * t[free][1]];
                    best = best.max(w[0] * d[0] + w[1] * d[1]);
                }
            }
        }
        0.1 / n as f64 * best
    }

    #[test]
    fn the_reach_along_a_direction_is_the_zonotopes_boundary_and_the_best_direction_the_farthest() {
        let centers = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5], [0.3, 0.1]];
        let bounds = [0.9, 0.5, 0.7, 0.95, 0.3];
        for p in [[0.5, 0.0], [-0.75, 0.25], [0.3, 0.2], [0.9, -0.45]] {
            let (f, d) = max_force_at(&centers, &bounds, 0.1, 0, 0.0, p);
            assert!((max_force_in(&centers, &bounds, 0.1, 0, 0.0, p, d) - f).abs() < 1e-12 * f);
            for i in 0..360 {
                let a = i as f64 * core::f64::consts::TAU / 360.0;
                let d = [a.cos(), a.sin()];
                let along = max_force_in(&centers, &bounds, 0.1, 0, 0.0, p, d);
                assert!(along <= f * (1.0 + 1e-12));
                let sampled = reach_by_sampling(&centers, &bounds, p, d);
                assert!((along - sampled).abs() < 1e-12, "{p:?} {d:?}: {along} vs {sampled}");
            }
        }
    }

    #[test]
    fn a_sparse_cycle_gives_the_strongest_center_outside_the_keep_out() {
        let centers = [[0.0, 0.0], [1.0, 0.0]];
        let (f, _) = max_force_at(&centers, &[0.9, 0.5], 0.1, 8, 0.1, [0.05, 0.0]);
        assert!((f - 0.05).abs() < 1e-15, "{f}");
        let m = max_force_on_plate(&centers, &[0.9, 0.5], 0.1, 8, 0.1, [0.5, 0.5]);
        assert!((m.force - 0.09).abs() < 1e-15, "{m:?}");
        // Along a tangent, that center alone; between two tangents, the chord.
        let p = [0.5, 0.5];
        let t0 = unit_tangent(p, centers[0]).0;
        assert!((max_force_in(&centers, &[0.9, 0.5], 0.1, 8, 0.1, p, t0) - 0.09).abs() < 1e-12);
        let t1 = unit_tangent(p, centers[1]).0;
        let (a, b) = ([0.09 * t0[0], 0.09 * t0[1]], [0.05 * t1[0], 0.05 * t1[1]]);
        let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let n = mid[0].hypot(mid[1]);
        let along = max_force_in(&centers, &[0.9, 0.5], 0.1, 8, 0.1, p, [mid[0] / n, mid[1] / n]);
        assert!((along - n).abs() < 1e-12, "{along} vs {n}");
    }
}
