//! Coulomb stick–slip of one part over one (sub)step in which the plate's
//! acceleration at the part is constant.
//!
//! State: the relative twist ξ = plate − part (linear velocity at the part's
//! center, angular velocity). While sliding, dξ/dt = a − G(ξ) where a is the
//! plate's twist acceleration at the part and G the kinetic friction
//! (per unit mass, torque per unit inertia), which depends only on ξ's
//! direction. The step is cut at the instants where ξ comes closest to zero
//! along its current straight path (event location), so a reversal inside a
//! step is placed exactly rather than smeared over the step; at relative rest
//! the part sticks if the force it needs is inside the static limit surface
//! (|F| ≤ μ_s·m·g for a point; for a disc, the curve of its face, to the
//! table's interpolation; for a polygon, its contact points' limit, to
//! Newton's tolerance, erring towards sticking).
//! Kinetic friction sums over a part's contact points, except for a disc,
//! whose uniform pressure over the face is integrated exactly
//! ([`super::disc_friction`]).
//! No velocity regularisation: friction has full magnitude at any |ξ| > 0.

use super::disc_friction;
use super::part::Body;
use super::polygon_limit;

/// Pieces per step before the remainder is taken with one midpoint piece.
const MAX_PIECES: usize = 8;

#[derive(Debug, Clone, Copy)]
pub(crate) struct Coulomb {
    /// μ_k·g and μ_s·g (m/s²).
    pub kinetic: f64,
    pub stat: f64,
}

impl Coulomb {
    /// Both coefficients times `scale` (a lane's `mu_scale`).
    #[inline(always)]
    pub fn scaled(self, scale: f64) -> Self {
        Self { kinetic: self.kinetic * scale, stat: self.stat * scale }
    }
}

/// Twist inner product with the part's I/m `rho2` weighting the spin.
#[inline(always)]
pub(crate) fn twist_dot(rho2: f64, x: [f64; 3], y: [f64; 3]) -> f64 {
    x[0] * y[0] + x[1] * y[1] + rho2 * x[2] * y[2]
}

#[inline]
fn dot(b: &Body, x: [f64; 3], y: [f64; 3]) -> f64 {
    twist_dot(b.rho2, x, y)
}

/// Kinetic friction on the part for relative twist `xi` (any scale).
#[inline]
fn kinetic(b: &Body, rot: (f64, f64), xi: [f64; 3], ck: f64) -> [f64; 3] {
    if !b.extended {
        let n2 = xi[0] * xi[0] + xi[1] * xi[1];
        if n2 > 0.0 {
            let s = ck / n2.sqrt();
            return [s * xi[0], s * xi[1], 0.0];
        }
        return [0.0; 3];
    }
    if b.disc {
        return disc_friction::kinetic(disc_friction::table(), b.radius, b.rho2, xi, ck);
    }
    let (sn, cs) = rot;
    let mut f = [0.0; 3];
    for c in 0..b.n_contacts {
        let p = b.contacts[c];
        let r = [cs * p[0] - sn * p[1], sn * p[0] + cs * p[1]];
        let wx = xi[0] - xi[2] * r[1];
        let wy = xi[1] + xi[2] * r[0];
        let n2 = wx * wx + wy * wy;
        if n2 > 0.0 {
            let s = ck * b.weights[c] / n2.sqrt();
            let (fx, fy) = (s * wx, s * wy);
            f[0] += fx;
            f[1] += fy;
            f[2] += r[0] * fy - r[1] * fx;
        }
    }
    f[2] /= b.rho2;
    f
}

/// Can static friction supply the acceleration `a` (part moving with plate)?
/// `rot` is (sin, cos) of a polygon's angle.
#[inline]
fn sticks(b: &Body, rot: (f64, f64), a: [f64; 3], cs: f64) -> bool {
    if !b.extended {
        return a[0] * a[0] + a[1] * a[1] <= cs * cs;
    }
    if b.disc {
        return disc_friction::sticks(disc_friction::table(), b.radius, b.rho2, a, cs);
    }
    // The load in the body frame, per μ_s m g.
    let (sn, cn) = rot;
    let f = [(cn * a[0] + sn * a[1]) / cs, (cn * a[1] - sn * a[0]) / cs];
    let n = b.n_contacts;
    let (r, w) = (&b.contacts[..n], &b.weights[..n]);
    polygon_limit::holds(r, w, &b.limit, b.torsion_lever, f, b.rho2 * a[2] / cs)
}

/// Part twist velocity and displacement over a piece of length `s` with
/// constant acceleration `g`.
/// N = 3 for a twist (x, y, θ), 2 for a point part.
#[inline(always)]
fn advance<const N: usize>(vp: &mut [f64; N], disp: &mut [f64; N], g: [f64; N], s: f64) {
    for i in 0..N {
        disp[i] += vp[i] * s + 0.5 * g[i] * s * s;
        vp[i] += g[i] * s;
    }
}

/// Integrate one step of length `h`. `xi` is plate − part at the start,
/// `vp` the part twist (updated), `a` the plate twist acceleration at the
/// part. Returns the part displacement (x, y, θ). `stuck` is the stick state.
// The simulator's innermost kernel (per part, per substep): every input
// varies per call, so each stays a plain argument.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn step(
    b: &Body,
    angle: f64,
    mut xi: [f64; 3],
    vp: &mut [f64; 3],
    a: [f64; 3],
    h: f64,
    mu: Coulomb,
    stuck: &mut bool,
) -> [f64; 3] {
    // Only contact points turn with the part; a uniform disc's friction does not.
    let rot = if b.extended && !b.disc { angle.sin_cos() } else { (0.0, 1.0) };
    let ck = mu.kinetic;
    let mut disp = [0.0; 3];
    let mut rem = h;
    let scale = dot(b, a, a).sqrt() + ck;
    // Relative speeds below this count as relative rest.
    let tol = 1e-9 * scale * h;
    for piece in 0..MAX_PIECES {
        if rem <= 0.0 {
            break;
        }
        if *stuck {
            if sticks(b, rot, a, mu.stat) {
                advance(vp, &mut disp, a, rem);
                return disp;
            }
            *stuck = false;
            xi = [0.0; 3];
        }
        let at_rest = dot(b, xi, xi) <= tol * tol;
        if at_rest {
            // Friction absorbs the residual; then stick or depart along a.
            for i in 0..3 {
                vp[i] += xi[i];
            }
            xi = [0.0; 3];
            if sticks(b, rot, a, mu.stat) {
                *stuck = true;
                advance(vp, &mut disp, a, rem);
                return disp;
            }
        }
        let g = kinetic(b, rot, if at_rest { a } else { xi }, ck);
        let bv = [a[0] - g[0], a[1] - g[1], a[2] - g[2]];
        let bb = dot(b, bv, bv);
        let s_star = if bb > 0.0 { -dot(b, xi, bv) / bb } else { f64::INFINITY };
        if piece + 1 < MAX_PIECES && s_star > 1e-3 * h && s_star < rem {
            // Closest approach to relative rest inside this step.
            advance(vp, &mut disp, g, s_star);
            for i in 0..3 {
                xi[i] += bv[i] * s_star;
            }
            rem -= s_star;
            if dot(b, xi, xi) <= (1e-6 * scale * h).powi(2) {
                for i in 0..3 {
                    vp[i] += xi[i];
                }
                xi = [0.0; 3];
            }
            continue;
        }
        // No approach to rest: midpoint direction for the rest of the step.
        let xm = [xi[0] + 0.5 * bv[0] * rem, xi[1] + 0.5 * bv[1] * rem, xi[2] + 0.5 * bv[2] * rem];
        let g2 = if dot(b, xm, xm) > tol * tol { kinetic(b, rot, xm, ck) } else { g };
        advance(vp, &mut disp, g2, rem);
        rem = 0.0;
    }
    if rem > 0.0 {
        let g = if *stuck { a } else { kinetic(b, rot, if dot(b, xi, xi) > tol * tol { xi } else { a }, ck) };
        advance(vp, &mut disp, g, rem);
    }
    disp
}

/// [`step`] for a point part, the common case made cheap: one branch while
/// stuck, two square roots while sliding, and no division in the event test.
/// Same model and event logic; the rest tolerances use (|a| + μ_k g)² ≤
/// 2(|a|² + (μ_k g)²) to avoid a square root.
#[inline]
pub(crate) fn step_point(
    mut xi: [f64; 2],
    v: &mut [f64; 2],
    a: [f64; 2],
    h: f64,
    mu: Coulomb,
    stuck: &mut bool,
) -> [f64; 2] {
    let ck = mu.kinetic;
    let aa = a[0] * a[0] + a[1] * a[1];
    let sticks = aa <= mu.stat * mu.stat;
    let mut disp = [0.0; 2];
    if *stuck {
        if sticks {
            advance(v, &mut disp, a, h);
            return disp;
        }
        *stuck = false;
        xi = [0.0; 2];
    }
    let scale2 = 2.0 * (aa + ck * ck) * h * h;
    let (tol2, snap2) = (1e-18 * scale2, 1e-12 * scale2);
    let dot = |x: [f64; 2], y: [f64; 2]| x[0] * y[0] + x[1] * y[1];
    let mut rem = h;
    for piece in 0..MAX_PIECES {
        let n2 = dot(xi, xi);
        let at_rest = n2 <= tol2;
        if at_rest {
            v[0] += xi[0];
            v[1] += xi[1];
            xi = [0.0; 2];
            if sticks {
                *stuck = true;
                advance(v, &mut disp, a, rem);
                return disp;
            }
        }
        // Leaving rest, friction opposes a (|a| > μ_s g > 0 here).
        let (dir, d2) = if at_rest { (a, aa) } else { (xi, n2) };
        let k = ck / d2.sqrt();
        let g = [k * dir[0], k * dir[1]];
        let bv = [a[0] - g[0], a[1] - g[1]];
        let bb = dot(bv, bv);
        // s* = −ξ·b / b·b, compared without dividing (b·b > 0).
        let num = -dot(xi, bv);
        if piece + 1 < MAX_PIECES && bb > 0.0 && num > 1e-3 * h * bb && num < rem * bb {
            let s_star = num / bb;
            advance(v, &mut disp, g, s_star);
            xi = [xi[0] + bv[0] * s_star, xi[1] + bv[1] * s_star];
            rem -= s_star;
            if dot(xi, xi) <= snap2 {
                v[0] += xi[0];
                v[1] += xi[1];
                xi = [0.0; 2];
            }
            continue;
        }
        let xm = [xi[0] + 0.5 * bv[0] * rem, xi[1] + 0.5 * bv[1] * rem];
        let m2 = dot(xm, xm);
        let g2 = if m2 > tol2 {
            let k = ck / m2.sqrt();
            [k * xm[0], k * xm[1]]
        } else {
            g
        };
        advance(v, &mut disp, g2, rem);
        return disp;
    }
    // Out of pieces (MAX_PIECES − 1 events in one step): plain Euler.
    let g = if dot(xi, xi) > tol2 {
        let k = ck / dot(xi, xi).sqrt();
        [k * xi[0], k * xi[1]]
    } else {
        let k = ck / aa.sqrt();
        [k * a[0], k * a[1]]
    };
    advance(v, &mut disp, g, rem);
    disp
}
