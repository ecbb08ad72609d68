//! Discs four at a time, over [`Group`]s: the common cases of
//! [`friction::step`] for a disc (stuck and staying stuck; sliding with no
//! approach to rest in the step) in branch-free lanes, as
//! [`super::point_lanes`] does for points. Any other live lane is redone by
//! the scalar routine from the same inputs. The lanes use the scalar
//! routine's operations in the same order and nothing is fused, so both
//! paths give the same bits.

use super::disc_friction::{self, Table};
use super::friction::{self, Coulomb, twist_dot};
use super::lanes::{Group, W};
use super::part::Body;
use super::point_lanes::{PlateNow, relative};

/// (a, ξ) as twists (x, y, θ) for a part at `pos` moving at `v` and
/// spinning at `w`: the plate's acceleration along the part's path, and
/// plate − part (the inputs of [`friction::step`]).
#[inline(always)]
pub(crate) fn relative_twist(pl: &PlateNow, pos: [f64; 2], v: [f64; 2], w: f64) -> ([f64; 3], [f64; 3]) {
    let (a, xi) = relative(pl, pos, v);
    ([a[0], a[1], pl.acc.theta], [xi[0], xi[1], pl.vel.theta - w])
}

/// Every live lane of `groups` (the discs); `part_of` maps their lanes to
/// parts, for the bodies the scalar routine needs. Inlined into the
/// simulator's step, which has an AVX2 clone.
#[inline(always)]
pub(crate) fn step_discs(
    pl: &PlateNow,
    groups: &mut [Group],
    part_of: &[usize],
    bodies: &[Body],
    s: f64,
    mu: Coulomb,
    table: &Table,
) {
    for (gi, g) in groups.iter_mut().enumerate() {
        let (mut a, mut xi) = ([[0.0; W]; 3], [[0.0; W]; 3]);
        for k in 0..W {
            let (ak, xk) = relative_twist(pl, [g.x[k], g.y[k]], [g.vx[k], g.vy[k]], g.w[k]);
            for c in 0..3 {
                (a[c][k], xi[c][k]) = (ak[c], xk[c]);
            }
        }
        let (o, fast) = fast_discs(&a, &xi, g, s, mu, table);
        for k in 0..W {
            let f = fast[k] & g.live[k];
            g.x[k] = if f { g.x[k] + o[0][k] } else { g.x[k] };
            g.y[k] = if f { g.y[k] + o[1][k] } else { g.y[k] };
            g.angle[k] = if f { g.angle[k] + o[2][k] } else { g.angle[k] };
            g.vx[k] = if f { o[3][k] } else { g.vx[k] };
            g.vy[k] = if f { o[4][k] } else { g.vy[k] };
            g.w[k] = if f { o[5][k] } else { g.w[k] };
        }
        for k in 0..W {
            if g.live[k] & !fast[k] {
                let at = |v: &[[f64; W]; 3]| [v[0][k], v[1][k], v[2][k]];
                let mu = mu.scaled(g.mu_scale[k]);
                step_lane(g, k, &bodies[part_of[gi * W + k]], at(&a), at(&xi), s, mu);
            }
        }
    }
}

/// The two common cases of `step` for a disc, without branches, in phases:
/// LLVM vectorises the arithmetic phases, and the table lookups between them
/// are plain loads lane by lane. A lane is fast if stuck and staying stuck,
/// or sliding, not at rest and with no closest approach to rest inside the
/// step; then its part of the result (displacement (x, y, θ), then the
/// new twist) is exactly what the scalar routine gives. `a` and `ξ` are the
/// scalar routine's inputs, lane by lane; `g` gives the rest.
#[inline(always)]
fn fast_discs(
    a: &[[f64; W]; 3],
    xi: &[[f64; W]; 3],
    g: &Group,
    h: f64,
    mu: Coulomb,
    table: &Table,
) -> ([[f64; W]; 6], [bool; W]) {
    let ck = g.mu_scale.map(|m| mu.kinetic * m);
    let cs = g.mu_scale.map(|m| mu.stat * m);
    let lane3 = |v: &[[f64; W]; 3], k: usize| [v[0][k], v[1][k], v[2][k]];
    let mut out = [[0.0; W]; 6];
    let (mut n2, mut t2, mut coef) = ([0.0; W], [0.0; W], [[0.0; 2]; W]);
    let (mut load2, mut z, mut limit) = ([0.0; W], [0.0; W], [0.0; W]);
    // As `Body::new` sets them for a disc.
    let rho2 = g.radius.map(|r| 0.5 * r * r);
    for k in 0..W {
        (n2[k], t2[k]) = disc_friction::kinetic_args(g.radius[k], lane3(xi, k));
        (load2[k], z[k]) = disc_friction::static_args(g.radius[k], rho2[k], lane3(a, k), cs[k]);
    }
    for k in 0..W {
        coef[k] = disc_friction::lookup(table, t2[k]);
        limit[k] = disc_friction::limit_lookup(table, z[k]);
    }
    let mut g1 = [[0.0; W]; 3];
    let mut xm = [[0.0; W]; 3];
    let mut event = [false; W];
    for k in 0..W {
        let (a, xi, r) = (lane3(a, k), lane3(xi, k), g.radius[k]);
        let dot = |x: [f64; 3], y: [f64; 3]| twist_dot(rho2[k], x, y);
        let gk = disc_friction::kinetic_finish(r, rho2[k], xi, n2[k], coef[k], ck[k]);
        let bv = [a[0] - gk[0], a[1] - gk[1], a[2] - gk[2]];
        let bb = dot(bv, bv);
        let s_star = if bb > 0.0 { -dot(xi, bv) / bb } else { f64::INFINITY };
        event[k] = (s_star > 1e-3 * h) & (s_star < h);
        for c in 0..3 {
            g1[c][k] = gk[c];
            xm[c][k] = xi[c] + 0.5 * bv[c] * h;
        }
        (n2[k], t2[k]) = disc_friction::kinetic_args(r, lane3(&xm, k));
    }
    for k in 0..W {
        coef[k] = disc_friction::lookup(table, t2[k]);
    }
    let mut fast = [false; W];
    for k in 0..W {
        let (a, xi, r) = (lane3(a, k), lane3(xi, k), g.radius[k]);
        let dot = |x: [f64; 3], y: [f64; 3]| twist_dot(rho2[k], x, y);
        let (stuck, v) = (g.stuck[k], [g.vx[k], g.vy[k], g.w[k]]);
        let scale = dot(a, a).sqrt() + ck[k];
        let tol = 1e-9 * scale * h;
        let sticks = disc_friction::sticks_with(load2[k], limit[k]);
        let at_rest = dot(xi, xi) <= tol * tol;
        let xmk = lane3(&xm, k);
        let gm = disc_friction::kinetic_finish(r, rho2[k], xmk, n2[k], coef[k], ck[k]);
        let moving = dot(xmk, xmk) > tol * tol;
        for c in 0..3 {
            let g2 = if moving { gm[c] } else { g1[c][k] };
            let gl = if stuck { a[c] } else { g2 };
            // `0.0 +` as in `step`, whose displacement starts from zero.
            out[c][k] = 0.0 + (v[c] * h + 0.5 * gl * h * h);
            out[3 + c][k] = v[c] + gl * h;
        }
        fast[k] = (stuck & sticks) | (!stuck & !at_rest & !event[k]);
    }
    (out, fast)
}

/// Lane `k` of any extended part (`body`) by the scalar routine, from its
/// (a, ξ): a disc lane off the fast path (about one lane-step in twenty,
/// hence out of line), and every polygon lane.
#[inline(never)]
pub(crate) fn step_lane(
    g: &mut Group,
    k: usize,
    body: &Body,
    a: [f64; 3],
    xi: [f64; 3],
    s: f64,
    mu: Coulomb,
) {
    debug_assert!(body.extended && (!body.disc || body.radius == g.radius[k]));
    let mut vp = [g.vx[k], g.vy[k], g.w[k]];
    let d = friction::step(body, g.angle[k], xi, &mut vp, a, s, mu, &mut g.stuck[k]);
    g.x[k] += d[0];
    g.y[k] += d[1];
    g.angle[k] += d[2];
    [g.vx[k], g.vy[k], g.w[k]] = vp;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::lanes::{LaneKind, Lanes};
    use crate::sim::part::{BodyShape, PartSpec, PartState};
    use proptest::prelude::*;
    use upm_motion::Twist;

    const MU: Coulomb = Coulomb { kinetic: 0.25 * 9.81, stat: 0.3 * 9.81 };

    fn disc(r: f64) -> Body {
        let spec =
            PartSpec { shape: BodyShape::Disc { radius: r }, mass: 0.04, position: [0.0; 2], angle: 0.0 };
        Body::new(&spec).expect("disc").0
    }

    /// `fast_discs` on lane 0 alone: (displacement, new twist) and fast.
    fn one_lane(a: [f64; 3], xi: [f64; 3], v: [f64; 3], stuck: bool, r: f64, h: f64) -> ([f64; 6], bool) {
        let mut g = Group::default();
        ([g.vx[0], g.vy[0], g.w[0]], g.stuck[0], g.radius[0]) = (v, stuck, r);
        let (mut al, mut xl) = ([[0.0; W]; 3], [[0.0; W]; 3]);
        for c in 0..3 {
            (al[c][0], xl[c][0]) = (a[c], xi[c]);
        }
        let (out, fast) = fast_discs(&al, &xl, &g, h, MU, disc_friction::table());
        (core::array::from_fn(|c| out[c][0]), fast[0])
    }

    proptest! {
        /// Where a lane calls itself fast, it gives the scalar routine's bits.
        #[test]
        fn fast_lanes_match_the_scalar_step(
            // Half the draws below the static limit (μ_s g ≈ 2.9), so that
            // stuck lanes that stay stuck are drawn too.
            a in prop_oneof![prop::array::uniform3(-3.0f64..3.0), prop::array::uniform3(-30.0f64..30.0)],
            xi in prop::array::uniform3(-0.05f64..0.05),
            v in prop::array::uniform3(-0.5f64..0.5),
            r in 0.005f64..0.1,
            stuck: bool,
        ) {
            let (h, angle) = (1e-4, 0.7);
            let (out, fast) = one_lane(a, xi, v, stuck, r, h);
            let (mut vs, mut st) = (v, stuck);
            let d = friction::step(&disc(r), angle, xi, &mut vs, a, h, MU, &mut st);
            if fast {
                prop_assert_eq!(st, stuck);
                for i in 0..3 {
                    prop_assert_eq!(out[i].to_bits(), d[i].to_bits(), "displacement {}", i);
                    prop_assert_eq!(out[3 + i].to_bits(), vs[i].to_bits(), "velocity {}", i);
                }
            }
        }
    }

    /// The lanes are used, and the scalar fallback too, on a real run: six
    /// discs stepped in groups match the same discs stepped one at a time by
    /// the scalar routine, bit for bit; unused lanes never move.
    #[test]
    fn groups_match_discs_stepped_one_by_one() {
        let pl = PlateNow::SHAKING;
        let n = 6;
        let radius: Vec<f64> = (0..n).map(|i| 0.01 + 0.01 * i as f64).collect();
        let bodies: Vec<Body> = radius.iter().map(|&r| disc(r)).collect();
        let parts: Vec<PartState> = (0..n)
            .map(|i| PartState {
                position: [0.1 * i as f64 - 0.3, 0.05 * i as f64],
                velocity: [0.01 * i as f64, if i % 2 == 0 { 0.05 } else { 0.0 }],
                angular_velocity: if i % 3 == 0 { 0.0 } else { 2.0 - i as f64 },
                stuck: i == 3,
                ..PartState::default()
            })
            .collect();
        let mut lanes = Lanes::new(&parts, &vec![LaneKind::Disc; n], &vec![[1.0; 2]; n], &radius);
        let mut scalar = parts.clone();
        let unused = lanes.groups[1];
        let (mut fast, mut total, mut fast_stuck) = (0, 0, 0);
        // For the first 300 ticks the plate barely accelerates, so the disc
        // that starts stuck stays stuck.
        let calm = PlateNow { acc: Twist { x: 0.5, y: -0.3, theta: 2.0 }, ..pl };
        for tick in 0..2000 {
            let pl = if tick < 300 { calm } else { pl };
            step_discs(&pl, &mut lanes.groups, &lanes.part_of, &bodies, 1e-4, MU, disc_friction::table());
            for (p, b) in scalar.iter_mut().zip(&bodies) {
                let (a, xi) = relative_twist(&pl, p.position, p.velocity, p.angular_velocity);
                let mut vp = [p.velocity[0], p.velocity[1], p.angular_velocity];
                let v = vp;
                let lane = one_lane(a, xi, v, p.stuck, b.radius, 1e-4).1;
                (fast, total) = (fast + lane as u32, total + 1);
                fast_stuck += (lane & p.stuck) as u32;
                let d = friction::step(b, p.angle, xi, &mut vp, a, 1e-4, MU, &mut p.stuck);
                p.position = [p.position[0] + d[0], p.position[1] + d[1]];
                p.angle += d[2];
                p.velocity = [vp[0], vp[1]];
                p.angular_velocity = vp[2];
            }
        }
        let mut back = vec![PartState::default(); n];
        lanes.mirror(&mut back);
        assert_eq!(back, scalar);
        assert_eq!(lanes.groups[1].x[3], unused.x[3]);
        assert!(fast > 0 && fast < total, "fast lane-steps {fast} of {total}: both paths must be used");
        assert!(fast_stuck > 0, "no fast lane-step was a stuck disc staying stuck");
        assert_ne!(back[0].position, parts[0].position);
        assert_ne!(back[1].angle, parts[1].angle);
    }
}
