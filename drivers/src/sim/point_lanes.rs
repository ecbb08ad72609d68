//! Point parts four at a time, over [`Group`]s: the common cases of
//! [`friction::step_point`] (stuck and staying stuck; sliding with no
//! approach to rest in the step) in four branch-free lanes. A lane that
//! needs anything else (at rest, breaking loose, a reversal inside the step)
//! is redone by the scalar routine from the same inputs. The lanes use the
//! scalar routine's operations in the same order, IEEE `sqrt` and `/` are
//! correctly rounded and nothing is fused, so both paths give the same bits.

use super::friction::{self, Coulomb};
use super::lanes::{Group, W};
use upm_motion::Twist;

/// Plate state held constant over one substep.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PlateNow {
    pub x: f64,
    pub y: f64,
    pub vel: Twist,
    pub acc: Twist,
}

#[cfg(test)]
impl PlateNow {
    /// A plate off its origin, moving and accelerating on every axis, hard
    /// enough that parts slide: the lanes' tests step parts against it.
    pub const SHAKING: Self = Self {
        x: 1e-4,
        y: -2e-4,
        vel: Twist { x: 0.05, y: -0.02, theta: 0.3 },
        acc: Twist { x: 30.0, y: -12.0, theta: 80.0 },
    };
}

/// (a, ξ) of one point part at `pos` moving at `v`: the plate's
/// acceleration along the part's path and plate − part velocity at the part
/// (the inputs of `step_point`).
#[inline(always)]
pub(crate) fn relative(pl: &PlateNow, pos: [f64; 2], v: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    let (vel, acc) = (pl.vel, pl.acc);
    let (rx, ry) = (pos[0] - pl.x, pos[1] - pl.y);
    let (ux, uy) = (v[0] - vel.x, v[1] - vel.y);
    let a = [acc.x - acc.theta * ry - vel.theta * uy, acc.y + acc.theta * rx + vel.theta * ux];
    let xi = [-vel.theta * ry - ux, vel.theta * rx - uy];
    (a, xi)
}

/// Lane `k` of `g`, scalar; `mu` already the lane's (as every lane
/// routine takes it).
#[inline(always)]
fn step_lane(pl: &PlateNow, g: &mut Group, k: usize, s: f64, mu: Coulomb) {
    let mut v = [g.vx[k], g.vy[k]];
    let (a, xi) = relative(pl, [g.x[k], g.y[k]], v);
    let d = friction::step_point(xi, &mut v, a, s, mu, &mut g.stuck[k]);
    g.x[k] += d[0];
    g.y[k] += d[1];
    [g.vx[k], g.vy[k]] = v;
}

/// Groups stepped side by side: each lane's chain of square roots and
/// divisions is long, and issuing several groups' chains together hides
/// their latency.
const BLOCK: usize = 4;

/// Every live lane of `groups` (the point parts). Inlined into the
/// simulator's step, which has an AVX2 clone.
#[inline(always)]
pub(crate) fn step_points(pl: &PlateNow, groups: &mut [Group], s: f64, mu: Coulomb) {
    for block in groups.chunks_mut(BLOCK) {
        step_block(pl, block, s, mu);
    }
}

/// Up to [`BLOCK`] groups, in phases over all of them: the first friction
/// direction, then the rest of the fast path, then the write-back (where
/// live and fast) and the scalar routine for the other live lanes.
#[inline(always)]
fn step_block(pl: &PlateNow, block: &mut [Group], s: f64, mu: Coulomb) {
    let mut a = [[[0.0; W]; 2]; BLOCK];
    let mut xi = [[[0.0; W]; 2]; BLOCK];
    let mut n2 = [[0.0; W]; BLOCK];
    let mut kk = [[0.0; W]; BLOCK];
    // Plain arrays in and out: LLVM vectorises the lane loops (ymm in the
    // AVX2 clone).
    for (b, g) in block.iter().enumerate() {
        for k in 0..W {
            let (ak, xk) = relative(pl, [g.x[k], g.y[k]], [g.vx[k], g.vy[k]]);
            [a[b][0][k], a[b][1][k]] = ak;
            [xi[b][0][k], xi[b][1][k]] = xk;
            (n2[b][k], kk[b][k]) = direction(xk, mu.scaled(g.mu_scale[k]));
        }
    }
    for (b, g) in block.iter_mut().enumerate() {
        let mut out = [[0.0; W]; 4];
        let mut lane = [Lane::default(); W];
        for k in 0..W {
            let v = [g.vx[k], g.vy[k]];
            let (ak, xk) = ([a[b][0][k], a[b][1][k]], [xi[b][0][k], xi[b][1][k]]);
            let mu = mu.scaled(g.mu_scale[k]);
            let (r, l) = fast_lane(ak, xk, (n2[b][k], kk[b][k]), v, g.stuck[k], s, mu);
            for c in 0..4 {
                out[c][k] = r[c];
            }
            lane[k] = Lane { fast: l.fast & g.live[k], event: l.event & g.live[k] };
        }
        let mut done = lane.map(|l| l.fast);
        // About one lane in twenty has an event: take them four at a time
        // too, when the group has any.
        if lane.iter().fold(false, |any, l| any | l.event) {
            let mut stuck = g.stuck;
            for k in 0..W {
                let (ak, xk) = ([a[b][0][k], a[b][1][k]], [xi[b][0][k], xi[b][1][k]]);
                let mu = mu.scaled(g.mu_scale[k]);
                let (r, st, ok) = event_lane(ak, xk, kk[b][k], [g.vx[k], g.vy[k]], s, mu);
                let take = lane[k].event & ok;
                for c in 0..4 {
                    out[c][k] = if take { r[c] } else { out[c][k] };
                }
                stuck[k] = if take { st } else { stuck[k] };
                done[k] |= take;
            }
            g.stuck = stuck;
        }
        for k in 0..W {
            let f = done[k];
            g.x[k] = if f { g.x[k] + out[0][k] } else { g.x[k] };
            g.y[k] = if f { g.y[k] + out[1][k] } else { g.y[k] };
            g.vx[k] = if f { out[2][k] } else { g.vx[k] };
            g.vy[k] = if f { out[3][k] } else { g.vy[k] };
        }
        for k in 0..W {
            if g.live[k] & !done[k] {
                step_lane(pl, g, k, s, mu.scaled(g.mu_scale[k]));
            }
        }
    }
}

/// |ξ|² and μ_k g / |ξ| (the scale of the start friction direction).
#[inline(always)]
fn direction(xi: [f64; 2], mu: Coulomb) -> (f64, f64) {
    let n2 = xi[0] * xi[0] + xi[1] * xi[1];
    (n2, mu.kinetic / n2.sqrt())
}

/// The two common cases of `step_point` without branches: returns
/// (displacement, new velocity) and whether the lane was one of them
/// (stuck and staying stuck; sliding, not at rest, no event in the step).
#[inline(always)]
fn fast_lane(
    a: [f64; 2],
    xi: [f64; 2],
    (n2, k): (f64, f64),
    v: [f64; 2],
    stuck: bool,
    h: f64,
    mu: Coulomb,
) -> ([f64; 4], Lane) {
    let ck = mu.kinetic;
    let aa = a[0] * a[0] + a[1] * a[1];
    let sticks = aa <= mu.stat * mu.stat;
    let scale2 = 2.0 * (aa + ck * ck) * h * h;
    let tol2 = 1e-18 * scale2;
    let g = [k * xi[0], k * xi[1]];
    let b = [a[0] - g[0], a[1] - g[1]];
    let bb = b[0] * b[0] + b[1] * b[1];
    let num = -(xi[0] * b[0] + xi[1] * b[1]);
    let event = (bb > 0.0) & (num > 1e-3 * h * bb) & (num < h * bb);
    let m = [xi[0] + 0.5 * b[0] * h, xi[1] + 0.5 * b[1] * h];
    let m2 = m[0] * m[0] + m[1] * m[1];
    let k2 = ck / m2.sqrt();
    let moving = m2 > tol2;
    let g2 = [if moving { k2 * m[0] } else { g[0] }, if moving { k2 * m[1] } else { g[1] }];
    let gx = if stuck { a[0] } else { g2[0] };
    let gy = if stuck { a[1] } else { g2[1] };
    let sliding = !stuck & (n2 > tol2);
    let fast = (stuck & sticks) | (sliding & !event);
    // `0.0 +` as in step_point, whose displacement starts from zero (so a
    // −0.0 comes out +0.0 on both paths).
    let d = [0.0 + (v[0] * h + 0.5 * gx * h * h), 0.0 + (v[1] * h + 0.5 * gy * h * h)];
    ([d[0], d[1], v[0] + gx * h, v[1] + gy * h], Lane { fast, event: sliding & event })
}

/// What [`fast_lane`] found: `fast` if it took the step, `event` if the
/// lane slides into a closest approach to relative rest inside the step
/// (then [`event_lane`] may take it).
#[derive(Debug, Clone, Copy, Default)]
struct Lane {
    fast: bool,
    event: bool,
}

/// A sliding lane with one closest approach inside the step, as
/// `step_point` does it: up to the event, snap to relative rest if there,
/// then stick, leave rest along a, or slide on with a midpoint direction.
/// Returns (displacement, new velocity), the new stick flag, and false
/// where the rest of the step holds a second event (left to the scalar
/// routine). Same operations in the same order as `step_point`.
#[inline(always)]
fn event_lane(a: [f64; 2], xi: [f64; 2], k: f64, v: [f64; 2], h: f64, mu: Coulomb) -> ([f64; 4], bool, bool) {
    let ck = mu.kinetic;
    let dot = |x: [f64; 2], y: [f64; 2]| x[0] * y[0] + x[1] * y[1];
    let aa = dot(a, a);
    let sticks = aa <= mu.stat * mu.stat;
    let scale2 = 2.0 * (aa + ck * ck) * h * h;
    let (tol2, snap2) = (1e-18 * scale2, 1e-12 * scale2);
    let mut v = v;
    // Piece 1: to the closest approach.
    let g = [k * xi[0], k * xi[1]];
    let bv = [a[0] - g[0], a[1] - g[1]];
    let bb = dot(bv, bv);
    let s1 = -dot(xi, bv) / bb;
    let mut disp = [0.0 + (v[0] * s1 + 0.5 * g[0] * s1 * s1), 0.0 + (v[1] * s1 + 0.5 * g[1] * s1 * s1)];
    v = [v[0] + g[0] * s1, v[1] + g[1] * s1];
    let mut xi = [xi[0] + bv[0] * s1, xi[1] + bv[1] * s1];
    let rem = h - s1;
    let snap = dot(xi, xi) <= snap2;
    v = [if snap { v[0] + xi[0] } else { v[0] }, if snap { v[1] + xi[1] } else { v[1] }];
    xi = if snap { [0.0; 2] } else { xi };
    // Piece 2: at rest (stick or leave along a) or still sliding.
    let n2 = dot(xi, xi);
    let at_rest = n2 <= tol2;
    v = [if at_rest { v[0] + xi[0] } else { v[0] }, if at_rest { v[1] + xi[1] } else { v[1] }];
    xi = if at_rest { [0.0; 2] } else { xi };
    let stuck = at_rest & sticks;
    let (dir, d2) = if at_rest { (a, aa) } else { (xi, n2) };
    let k2 = ck / d2.sqrt();
    let g2 = [k2 * dir[0], k2 * dir[1]];
    let bv2 = [a[0] - g2[0], a[1] - g2[1]];
    let bb2 = dot(bv2, bv2);
    let num2 = -dot(xi, bv2);
    let again = (bb2 > 0.0) & (num2 > 1e-3 * h * bb2) & (num2 < rem * bb2);
    let xm = [xi[0] + 0.5 * bv2[0] * rem, xi[1] + 0.5 * bv2[1] * rem];
    let m2 = dot(xm, xm);
    let k3 = ck / m2.sqrt();
    let moving = m2 > tol2;
    let g3 = [if moving { k3 * xm[0] } else { g2[0] }, if moving { k3 * xm[1] } else { g2[1] }];
    let gl = if stuck { a } else { g3 };
    disp =
        [disp[0] + (v[0] * rem + 0.5 * gl[0] * rem * rem), disp[1] + (v[1] * rem + 0.5 * gl[1] * rem * rem)];
    v = [v[0] + gl[0] * rem, v[1] + gl[1] * rem];
    ([disp[0], disp[1], v[0], v[1]], stuck, stuck | !again)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::lanes::{LaneKind, Lanes};
    use crate::sim::part::PartState;
    use proptest::prelude::*;

    const MU: Coulomb = Coulomb { kinetic: 0.25 * 9.81, stat: 0.3 * 9.81 };

    proptest! {
        /// Where a lane calls itself fast, it gives the scalar routine's bits.
        #[test]
        fn fast_lanes_match_the_scalar_step(
            a in prop::array::uniform2(-20.0f64..20.0),
            xi in prop::array::uniform2(-0.05f64..0.05),
            v in prop::array::uniform2(-0.5f64..0.5),
            stuck: bool,
        ) {
            let h = 1e-4;
            let (out, lane) = fast_lane(a, xi, direction(xi, MU), v, stuck, h, MU);
            let fast = lane.fast;
            let (mut vs, mut st) = (v, stuck);
            let d = friction::step_point(if stuck { [0.0; 2] } else { xi }, &mut vs, a, h, MU, &mut st);
            if fast {
                prop_assert_eq!(out, [d[0], d[1], vs[0], vs[1]]);
                prop_assert_eq!(st, stuck);
            }
        }

        /// Where an event lane says it took the step, it gives the scalar
        /// routine's bits and stick flag (small ξ, so events are common).
        #[test]
        fn event_lanes_match_the_scalar_step(
            a in prop::array::uniform2(-20.0f64..20.0),
            xi in prop::array::uniform2(-0.003f64..0.003),
            v in prop::array::uniform2(-0.5f64..0.5),
        ) {
            let h = 1e-4;
            let (n2, k) = direction(xi, MU);
            let (_, lane) = fast_lane(a, xi, (n2, k), v, false, h, MU);
            let (out, stuck, ok) = event_lane(a, xi, k, v, h, MU);
            let (mut vs, mut st) = (v, false);
            let d = friction::step_point(xi, &mut vs, a, h, MU, &mut st);
            if lane.event && ok {
                prop_assert_eq!(out, [d[0], d[1], vs[0], vs[1]]);
                prop_assert_eq!(stuck, st);
            }
        }
    }

    /// A −0.0 displacement comes out +0.0 on both paths (bits, not ==).
    #[test]
    fn signed_zero_displacement_matches_the_scalar_step() {
        let (a, v, h) = ([-0.0, -0.0], [-0.0, -0.0], 1e-4);
        let (n2, k) = direction([0.0; 2], MU);
        let (out, lane) = fast_lane(a, [0.0; 2], (n2, k), v, true, h, MU);
        let (mut vs, mut st) = (v, true);
        let d = friction::step_point([0.0; 2], &mut vs, a, h, MU, &mut st);
        assert!(lane.fast);
        assert_eq!(out.map(f64::to_bits), [d[0], d[1], vs[0], vs[1]].map(f64::to_bits));
    }

    /// The event path is used, and for each way a step can end: stuck,
    /// leaving rest (ξ heading straight at zero, |a| above the static
    /// limit), and sliding on past the closest approach.
    #[test]
    fn event_lanes_cover_every_ending() {
        let (h, mut seen) = (1e-4, [0; 3]);
        for i in 0..40_000u32 {
            let f = |j: u32| (i.wrapping_mul(2_654_435_761).rotate_left(j) as f64 / u32::MAX as f64) - 0.5;
            let a = [10.0 * f(3), 10.0 * f(7)];
            // Every other case heads straight at relative rest.
            let straight = i % 2 == 0;
            let xi = if straight {
                [-1e-4 * f(11).abs() * a[0], -1e-4 * f(11).abs() * a[1]]
            } else {
                [0.006 * f(11), 0.006 * f(13)]
            };
            let v = [f(17), f(19)];
            let (n2, k) = direction(xi, MU);
            let (_, lane) = fast_lane(a, xi, (n2, k), v, false, h, MU);
            let (out, stuck, ok) = event_lane(a, xi, k, v, h, MU);
            if !(lane.event && ok) {
                continue;
            }
            let (mut vs, mut st) = (v, false);
            let d = friction::step_point(xi, &mut vs, a, h, MU, &mut st);
            assert_eq!((out, stuck), ([d[0], d[1], vs[0], vs[1]], st));
            seen[if stuck {
                0
            } else if straight {
                1
            } else {
                2
            }] += 1;
        }
        assert!(seen.iter().all(|&n| n > 0), "endings seen (stuck, leaving rest, sliding on): {seen:?}");
    }

    /// The lanes are used, and the fallback too, on a real run: seven parts
    /// stepped in groups match the same parts stepped one lane at a time,
    /// bit for bit; the unused lane never moves.
    #[test]
    fn groups_match_lanes_stepped_one_by_one() {
        let pl = PlateNow::SHAKING;
        let parts: Vec<PartState> = (0..7)
            .map(|i| PartState {
                position: [0.1 * i as f64 - 0.3, 0.05 * i as f64],
                velocity: [0.01 * i as f64, if i % 2 == 0 { 0.05 } else { 0.0 }],
                stuck: i == 3,
                ..PartState::default()
            })
            .collect();
        let mut lanes = Lanes::new(&parts, &[LaneKind::Point; 7], &[[1.0; 2]; 7], &[0.0; 7]);
        let mut one_by_one = lanes.clone();
        let unused = lanes.groups[1];
        for _ in 0..2000 {
            step_points(&pl, &mut lanes.groups, 1e-4, MU);
            for g in &mut one_by_one.groups {
                let live = g.live;
                for k in (0..W).filter(|&k| live[k]) {
                    step_lane(&pl, g, k, 1e-4, MU);
                }
            }
        }
        assert_eq!(lanes.groups, one_by_one.groups);
        assert_eq!(lanes.groups[1].x[3], unused.x[3]);
        assert_ne!(lanes.groups[0].x[0], parts[0].position[0]);
    }
}
