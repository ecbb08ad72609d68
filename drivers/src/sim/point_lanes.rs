//! Point parts four at a time: the common cases of [`friction::step_point`]
//! (stuck and staying stuck; sliding with no approach to rest in the step)
//! in four branch-free lanes. A lane that needs anything else (at rest,
//! breaking loose, a reversal inside the step) is redone by the scalar
//! routine from the same inputs. The lanes use the scalar routine's
//! operations in the same order, IEEE `sqrt` and `/` are correctly rounded
//! and nothing is fused, so both paths give the same bits.

use multiversion::multiversion;

use super::friction::{self, Coulomb};
use super::part::PartState;
use rt_core::motion::Twist;

/// Plate state held constant over one substep.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PlateNow {
    pub x: f64,
    pub y: f64,
    pub vel: Twist,
    pub acc: Twist,
}

/// (a, ξ) of one point part: the plate's acceleration along the part's path
/// and plate − part velocity at the part (the inputs of `step_point`).
#[inline(always)]
pub(crate) fn relative(pl: &PlateNow, p: &PartState) -> ([f64; 2], [f64; 2]) {
    let (vel, acc) = (pl.vel, pl.acc);
    let (rx, ry) = (p.position[0] - pl.x, p.position[1] - pl.y);
    let (ux, uy) = (p.velocity[0] - vel.x, p.velocity[1] - vel.y);
    let a = [acc.x - acc.theta * ry - vel.theta * uy, acc.y + acc.theta * rx + vel.theta * ux];
    let xi = [-vel.theta * ry - ux, vel.theta * rx - uy];
    (a, xi)
}

/// One point part, scalar.
#[inline(always)]
pub(crate) fn step_one(pl: &PlateNow, p: &mut PartState, s: f64, mu: Coulomb) {
    let (a, xi) = relative(pl, p);
    let d = friction::step_point(xi, &mut p.velocity, a, s, mu, &mut p.stuck);
    p.position[0] += d[0];
    p.position[1] += d[1];
}

/// Every point part in `points` (indices into `parts`), four lanes at a
/// time; the last group is padded with a repeated index that is not
/// written back. AVX2 clone where the CPU has it (nothing is fused, so both
/// clones give the same bits).
#[multiversion(targets("x86_64+avx2"))]
pub(crate) fn step_points(pl: &PlateNow, parts: &mut [PartState], points: &[usize], s: f64, mu: Coulomb) {
    for group in points.chunks(4) {
        let last = group[group.len() - 1];
        let idx = core::array::from_fn(|k| group.get(k).copied().unwrap_or(last));
        step_four(pl, parts, idx, group.len(), s, mu);
    }
}

/// Four point parts (indices into `parts`), lanes with scalar fallback;
/// only the first `real` lanes are written back.
#[inline(always)]
fn step_four(pl: &PlateNow, parts: &mut [PartState], idx: [usize; 4], real: usize, s: f64, mu: Coulomb) {
    let ps = idx.map(|i| parts[i]);
    let mut out = [[0.0; 4]; 4];
    let mut fast = [false; 4];
    // Branch-free lane body over plain arrays: LLVM vectorises this loop
    // (ymm in the AVX2 clone).
    for l in 0..4 {
        let p = &ps[l];
        let (a, xi) = relative(pl, p);
        let r = fast_lane(a, xi, p.velocity, p.stuck, s, mu);
        out[l] = r.0;
        fast[l] = r.1;
    }
    for (lane, &i) in idx.iter().enumerate().take(real) {
        let p = &mut parts[i];
        if !fast[lane] {
            step_one(pl, p, s, mu);
            continue;
        }
        let [dx, dy, vx, vy] = out[lane];
        p.position[0] += dx;
        p.position[1] += dy;
        p.velocity = [vx, vy];
    }
}

/// The two common cases of `step_point` without branches: returns
/// (displacement, new velocity) and whether the lane was one of them
/// (stuck and staying stuck; sliding, not at rest, no event in the step).
#[inline(always)]
fn fast_lane(a: [f64; 2], xi: [f64; 2], v: [f64; 2], stuck: bool, h: f64, mu: Coulomb) -> ([f64; 4], bool) {
    let ck = mu.kinetic;
    let aa = a[0] * a[0] + a[1] * a[1];
    let sticks = aa <= mu.stat * mu.stat;
    let scale2 = 2.0 * (aa + ck * ck) * h * h;
    let tol2 = 1e-18 * scale2;
    let n2 = xi[0] * xi[0] + xi[1] * xi[1];
    let k = ck / n2.sqrt();
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
            let (out, fast) = fast_lane(a, xi, v, stuck, h, MU);
            let (mut vs, mut st) = (v, stuck);
            let d = friction::step_point(if stuck { [0.0; 2] } else { xi }, &mut vs, a, h, MU, &mut st);
            if fast {
                prop_assert_eq!(out, [d[0], d[1], vs[0], vs[1]]);
                prop_assert_eq!(st, stuck);
            }
        }
    }

    /// The lanes are used, and the fallback too, on a real run: four parts
    /// stepped as a group match four stepped one by one, bit for bit.
    #[test]
    fn groups_match_parts_stepped_one_by_one() {
        let pl = PlateNow {
            x: 1e-4,
            y: -2e-4,
            vel: Twist { x: 0.05, y: -0.02, theta: 0.3 },
            acc: Twist { x: 30.0, y: -12.0, theta: 80.0 },
        };
        let mut parts: Vec<PartState> = (0..7)
            .map(|i| PartState {
                position: [0.1 * i as f64 - 0.3, 0.05 * i as f64],
                velocity: [0.01 * i as f64, if i % 2 == 0 { 0.05 } else { 0.0 }],
                stuck: i == 3,
                ..PartState::default()
            })
            .collect();
        let mut one_by_one = parts.clone();
        let idx: Vec<usize> = (0..parts.len()).collect();
        for _ in 0..2000 {
            step_points(&pl, &mut parts, &idx, 1e-4, MU);
            for p in &mut one_by_one {
                step_one(&pl, p, 1e-4, MU);
            }
        }
        assert_eq!(parts, one_by_one);
    }
}
