//! Point parts four at a time, over [`Group`]s: the common cases of
//! [`friction::step_point`] (stuck and staying stuck; sliding with no
//! approach to rest in the step) in four branch-free lanes. A lane that
//! needs anything else (at rest, breaking loose, a reversal inside the step)
//! is redone by the scalar routine from the same inputs. The lanes use the
//! scalar routine's operations in the same order, IEEE `sqrt` and `/` are
//! correctly rounded and nothing is fused, so both paths give the same bits.

use super::friction::{self, Coulomb};
use super::lanes::{Group, W};
use rt_core::motion::Twist;

/// Plate state held constant over one substep.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PlateNow {
    pub x: f64,
    pub y: f64,
    pub vel: Twist,
    pub acc: Twist,
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

/// Lane `k` of `g`, scalar.
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
            (n2[b][k], kk[b][k]) = direction(xk, mu);
        }
    }
    for (b, g) in block.iter_mut().enumerate() {
        let mut out = [[0.0; W]; 4];
        let mut fast = [false; W];
        for k in 0..W {
            let v = [g.vx[k], g.vy[k]];
            let (ak, xk) = ([a[b][0][k], a[b][1][k]], [xi[b][0][k], xi[b][1][k]]);
            let (r, f) = fast_lane(ak, xk, (n2[b][k], kk[b][k]), v, g.stuck[k], s, mu);
            for c in 0..4 {
                out[c][k] = r[c];
            }
            fast[k] = f & g.live[k];
        }
        for k in 0..W {
            let f = fast[k];
            g.x[k] = if f { g.x[k] + out[0][k] } else { g.x[k] };
            g.y[k] = if f { g.y[k] + out[1][k] } else { g.y[k] };
            g.vx[k] = if f { out[2][k] } else { g.vx[k] };
            g.vy[k] = if f { out[3][k] } else { g.vy[k] };
        }
        for k in 0..W {
            if g.live[k] & !fast[k] {
                step_lane(pl, g, k, s, mu);
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
) -> ([f64; 4], bool) {
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
    let fast = (stuck & sticks) | (!stuck & (n2 > tol2) & !event);
    let d = [v[0] * h + 0.5 * gx * h * h, v[1] * h + 0.5 * gy * h * h];
    ([d[0], d[1], v[0] + gx * h, v[1] + gy * h], fast)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::lanes::Lanes;
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
            let (out, fast) = fast_lane(a, xi, direction(xi, MU), v, stuck, h, MU);
            let (mut vs, mut st) = (v, stuck);
            let d = friction::step_point(if stuck { [0.0; 2] } else { xi }, &mut vs, a, h, MU, &mut st);
            if fast {
                prop_assert_eq!(out, [d[0], d[1], vs[0], vs[1]]);
                prop_assert_eq!(st, stuck);
            }
        }
    }

    /// The lanes are used, and the fallback too, on a real run: seven parts
    /// stepped in groups match the same parts stepped one lane at a time,
    /// bit for bit; the unused lane never moves.
    #[test]
    fn groups_match_lanes_stepped_one_by_one() {
        let pl = PlateNow {
            x: 1e-4,
            y: -2e-4,
            vel: Twist { x: 0.05, y: -0.02, theta: 0.3 },
            acc: Twist { x: 30.0, y: -12.0, theta: 80.0 },
        };
        let parts: Vec<PartState> = (0..7)
            .map(|i| PartState {
                position: [0.1 * i as f64 - 0.3, 0.05 * i as f64],
                velocity: [0.01 * i as f64, if i % 2 == 0 { 0.05 } else { 0.0 }],
                stuck: i == 3,
                ..PartState::default()
            })
            .collect();
        let mut lanes = Lanes::new(&parts, &[false; 7], &[[1.0; 2]; 7]);
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
