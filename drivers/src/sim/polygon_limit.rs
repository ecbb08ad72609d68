//! The static limit of a polygon: can friction at its contact points hold
//! a load? Exact for the contact model, with no table.
//!
//! Loads are per unit of μ_s m g, so the contact weights sum to 1 and the
//! loads static friction can supply are K = {(Σ f_i, Σ r_i × f_i) :
//! |f_i| ≤ w_i}. By maximum dissipation, (F, τ) is in K iff no sliding
//! twist draws more power from the load than friction can: |F| ≤ 1 (pure
//! sliding), and for every instantaneous centre c and either sense of spin
//!
//!   ψ±(c) = Σ w_i |r_i − c| ∓ (τ − c × F) ≥ 0.
//!
//! Each ψ is convex in c, so its minimum is found exactly: at a contact
//! point, where ψ has a kink (checked by its subgradient), or else by
//! damped Newton steps where ψ is smooth. Cheap tests settle most loads
//! first: outside if |F| > 1 or |τ| > Σ w_i |r_i|, inside the hull of the
//! pure forces and the two pure torques (±[`PolygonLimit::spin`]).

use super::part_capacity::MAX_CONTACTS;

/// Newton steps at most (quadratic convergence: a handful are used).
const MAX_NEWTON: usize = 40;

/// Distance in the plane (the arguments are small: no overflow guard).
#[inline(always)]
fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1])).sqrt()
}

/// Can friction at `contacts` (body frame, weights summing to 1; `limit`
/// built from them) hold the load: force `f` (body frame) and torque `tau`
/// (length units), both per μ_s m g? `lever` = Σ w_i |r_i| bounds |τ| over
/// every load.
pub(crate) fn holds(
    contacts: &[[f64; 2]],
    weights: &[f64],
    limit: &PolygonLimit,
    lever: f64,
    f: [f64; 2],
    tau: f64,
) -> bool {
    let ff = f[0] * f[0] + f[1] * f[1];
    // NaN loads are refused here too.
    if !(ff <= 1.0 && tau.abs() <= lever) {
        return false;
    }
    // Inside the hull of the pure forces and the two pure torques.
    if ff.sqrt() + tau.abs() / limit.spin <= 1.0 {
        return true;
    }
    min_psi(contacts, weights, limit, f, tau, 1.0) >= 0.0
        && min_psi(contacts, weights, limit, f, tau, -1.0) >= 0.0
}

/// What depends on the contact points alone, built once per part: at each
/// contact, Σ_i w_i |r_j − r_i| and the pull Σ_{i≠j} w_i (r_j − r_i)/|r_j −
/// r_i| of the others; and `spin`, the most torque friction gives with no
/// force.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct PolygonLimit {
    spread: [f64; MAX_CONTACTS],
    pull: [[f64; 2]; MAX_CONTACTS],
    /// min over the centre of spin c of Σ w_i |r_i − c| (c at the weighted
    /// geometric median, which is the centroid only for symmetric patches).
    pub spin: f64,
}

impl PolygonLimit {
    pub fn new(r: &[[f64; 2]], w: &[f64]) -> Self {
        let mut k = Self { spread: [0.0; MAX_CONTACTS], pull: [[0.0; 2]; MAX_CONTACTS], spin: 0.0 };
        for j in 0..r.len() {
            for i in j + 1..r.len() {
                let n = dist(r[j], r[i]);
                if n > 0.0 {
                    let u = [(r[j][0] - r[i][0]) / n, (r[j][1] - r[i][1]) / n];
                    k.spread[j] += w[i] * n;
                    k.spread[i] += w[j] * n;
                    k.pull[j] = [k.pull[j][0] + w[i] * u[0], k.pull[j][1] + w[i] * u[1]];
                    k.pull[i] = [k.pull[i][0] - w[j] * u[0], k.pull[i][1] - w[j] * u[1]];
                }
            }
        }
        k.spin = min_psi(r, w, &k, [0.0; 2], 0.0, 1.0);
        k
    }
}

/// min over c of ψ(c) = Σ w_i |r_i − c| + sense·(c × F − τ).
fn min_psi(r: &[[f64; 2]], w: &[f64], kinks: &PolygonLimit, f: [f64; 2], tau: f64, sense: f64) -> f64 {
    // c × F = ℓ·c with ℓ = (F_y, −F_x).
    let l = [sense * f[1], -sense * f[0]];
    let psi = |c: [f64; 2]| {
        let spread: f64 = r.iter().zip(w).map(|(ri, wi)| wi * dist(*ri, c)).sum();
        spread + l[0] * c[0] + l[1] * c[1] - sense * tau
    };
    // Kinks: if the minimum is at a contact point, it is at the lowest one,
    // and it is there iff the pull of the others and of the load is within
    // that contact's own weight.
    let at = |j: usize| kinks.spread[j] + l[0] * r[j][0] + l[1] * r[j][1] - sense * tau;
    let best = (1..r.len()).fold(0, |b, j| if at(j) < at(b) { j } else { b });
    let g = [l[0] + kinks.pull[best][0], l[1] + kinks.pull[best][1]];
    if g[0].hypot(g[1]) <= w[best] {
        return at(best);
    }
    // Smooth minimum: damped Newton from that contact point. Newton also
    // creeps towards a contact whose kink lies on its way (the line search
    // keeps cutting the step); on or within 10⁻⁶ of its size of a contact,
    // which is not the minimum, it leaves down the steepest edge.
    let scale = r.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
    let mut c = r[best];
    let mut value = at(best);
    for _ in 0..MAX_NEWTON {
        let (mut g, mut h, mut on) = (l, [0.0; 3], None);
        for (i, (ri, wi)) in r.iter().zip(w).enumerate() {
            let d = [c[0] - ri[0], c[1] - ri[1]];
            let n = dist(c, *ri);
            if n <= 1e-6 * scale {
                on = Some(i);
                continue;
            }
            let u = [d[0] / n, d[1] / n];
            g = [g[0] + wi * u[0], g[1] + wi * u[1]];
            let k = wi / n;
            h = [h[0] + k * (1.0 - u[0] * u[0]), h[1] - k * u[0] * u[1], h[2] + k * (1.0 - u[1] * u[1])];
        }
        let gn = g[0].hypot(g[1]);
        let det = h[0] * h[2] - h[1] * h[1];
        let step = match on {
            Some(i) if gn <= w[i] => break,
            Some(_) => [-0.5 * scale * g[0] / gn, -0.5 * scale * g[1] / gn],
            None if gn <= 1e-15 => break,
            None if det > 0.0 => [-(h[2] * g[0] - h[1] * g[1]) / det, -(h[0] * g[1] - h[1] * g[0]) / det],
            None => [-scale * g[0], -scale * g[1]],
        };
        // Converged: the step's predicted gain is below rounding.
        if -(g[0] * step[0] + g[1] * step[1]) <= 1e-15 * scale {
            break;
        }
        let mut t = 1.0;
        let mut next = [c[0] + step[0], c[1] + step[1]];
        let mut next_value = psi(next);
        while !(next_value < value) && t > 1e-9 {
            t *= 0.5;
            next = [c[0] + t * step[0], c[1] + t * step[1]];
            next_value = psi(next);
        }
        if !(next_value < value) {
            break;
        }
        (c, value) = (next, next_value);
    }
    value
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::part::{Body, BodyShape, PartSpec};
    use crate::sim::part_capacity::MAX_POLYGON_VERTICES;

    fn polygon(v: &[[f64; 2]]) -> Body {
        let mut vertices = [[0.0; 2]; MAX_POLYGON_VERTICES];
        vertices[..v.len()].copy_from_slice(v);
        let spec = PartSpec {
            shape: BodyShape::Polygon { vertices, count: v.len() },
            mass: 0.04,
            position: [0.0; 2],
            angle: 0.0,
        };
        Body::new(&spec).expect("polygon").0
    }

    /// The most power a load draws beyond friction over sliding twists
    /// (vx, vy, ω) sampled on a Fibonacci sphere: positive means the load
    /// breaks the part loose (independent of `holds`).
    fn excess(b: &Body, f: [f64; 2], tau: f64) -> f64 {
        let n = 40_000;
        let golden = core::f64::consts::PI * (1.0 + 5f64.sqrt());
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
                let (s, th) = ((1.0 - z * z).sqrt(), golden * (i as f64 + 0.5));
                let (vx, vy, w) = (s * th.cos(), s * th.sin(), z / b.radius);
                let friction: f64 = (0..b.n_contacts)
                    .map(|c| {
                        let p = b.contacts[c];
                        b.weights[c] * (vx - w * p[1]).hypot(vy + w * p[0])
                    })
                    .sum();
                f[0] * vx + f[1] * vy + tau * w - friction
            })
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Along 48 load directions, the boundary `holds` finds (by bisection)
    /// agrees with maximum dissipation to 1 %, on a square and on an
    /// irregular pentagon; and for the square it lies well inside the
    /// ellipse through pure force and pure torque somewhere.
    #[test]
    fn limit_agrees_with_maximum_dissipation() {
        let square = polygon(&[[-0.03, -0.03], [0.03, -0.03], [0.03, 0.03], [-0.03, 0.03]]);
        let pentagon = polygon(&[[0.0, 0.0], [0.05, -0.01], [0.07, 0.03], [0.03, 0.06], [-0.01, 0.03]]);
        // A thin triangle: its geometric median is far from its centroid.
        let sliver = polygon(&[[0.0, 0.0], [0.1, 0.0], [0.0, 0.01]]);
        for (name, b) in [("square", square), ("pentagon", pentagon), ("sliver", sliver)] {
            let (r, w) = (&b.contacts[..b.n_contacts], &b.weights[..b.n_contacts]);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            let mut worst_vs_ellipse = 1.0f64;
            for i in 0..48 {
                // Directions over the sphere of (F, τ / lever).
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / 48.0;
                let th = 2.4 * i as f64;
                let e =
                    [(1.0 - z * z).sqrt() * th.cos(), (1.0 - z * z).sqrt() * th.sin(), z * b.torsion_lever];
                let at = |k: f64| ([k * e[0], k * e[1]], k * e[2]);
                let (mut lo, mut hi) = (0.0, 2.0);
                assert!(!holds(r, w, &b.limit, b.torsion_lever, at(hi).0, at(hi).1));
                for _ in 0..50 {
                    let mid = 0.5 * (lo + hi);
                    let (f, tau) = at(mid);
                    if holds(r, w, &b.limit, b.torsion_lever, f, tau) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let (fi, ti) = at(0.99 * lo);
                let (fo, to) = at(1.01 * lo);
                assert!(excess(&b, fi, ti) <= 0.0, "{name}: 0.99 × limit breaks loose, direction {i}");
                assert!(excess(&b, fo, to) > 0.0, "{name}: 1.01 × limit holds, direction {i}");
                // e is on the ellipse, so `lo` is the exact limit over the ellipse's.
                worst_vs_ellipse = worst_vs_ellipse.min(lo);
            }
            if name == "square" {
                assert!(worst_vs_ellipse < 0.95, "square: the exact limit is within 5 % of the ellipse");
            }
        }
    }

    /// ψ's minimum by shrinking grids (ψ is convex, so the best cell of
    /// each grid holds the minimum): an independent check of `min_psi`.
    fn grid_min(r: &[[f64; 2]], w: &[f64], f: [f64; 2], tau: f64, sense: f64, span: f64) -> f64 {
        let psi = |c: [f64; 2]| {
            let spread: f64 = r.iter().zip(w).map(|(ri, wi)| wi * (ri[0] - c[0]).hypot(ri[1] - c[1])).sum();
            spread + sense * (c[0] * f[1] - c[1] * f[0] - tau)
        };
        let (mut centre, mut half) = ([0.0; 2], span);
        let mut best = f64::INFINITY;
        for _ in 0..30 {
            let mut arg = centre;
            for i in -20..=20 {
                for j in -20..=20 {
                    let c = [centre[0] + half * i as f64 / 20.0, centre[1] + half * j as f64 / 20.0];
                    let v = psi(c);
                    if v < best {
                        (best, arg) = (v, c);
                    }
                }
            }
            (centre, half) = (arg, half / 4.0);
        }
        r.iter().map(|&c| psi(c)).fold(best, f64::min)
    }

    /// `min_psi` finds ψ's minimum, at a contact point or between them,
    /// for 300 loads on the square and the pentagon.
    #[test]
    fn min_psi_matches_a_grid_search() {
        let square = polygon(&[[-0.03, -0.03], [0.03, -0.03], [0.03, 0.03], [-0.03, 0.03]]);
        let pentagon = polygon(&[[0.0, 0.0], [0.05, -0.01], [0.07, 0.03], [0.03, 0.06], [-0.01, 0.03]]);
        let mut rng = crate::rng::SplitMix64::new(7);
        let (mut at_contact, mut between) = (0, 0);
        for b in [square, pentagon] {
            let (r, w) = (&b.contacts[..b.n_contacts], &b.weights[..b.n_contacts]);
            for _ in 0..150 {
                let u =
                    |rng: &mut crate::rng::SplitMix64| 2.0 * (rng.next_u64() as f64 / u64::MAX as f64) - 1.0;
                // |F| < 1, where ψ is bounded below (`holds` refuses the rest).
                let (m, th) = (0.9 * u(&mut rng).abs(), 3.2 * u(&mut rng));
                let f = [m * th.cos(), m * th.sin()];
                let tau = u(&mut rng) * b.torsion_lever;
                let sense = if u(&mut rng) > 0.0 { 1.0 } else { -1.0 };
                let (got, want) = (
                    min_psi(r, w, &PolygonLimit::new(r, w), f, tau, sense),
                    grid_min(r, w, f, tau, sense, 50.0 * b.radius),
                );
                assert!((got - want).abs() < 1e-9 * b.radius, "{f:?} {tau} {sense}: {got} vs grid {want}");
                if r.iter().any(|&c| {
                    let spread: f64 =
                        r.iter().zip(w).map(|(ri, wi)| wi * (ri[0] - c[0]).hypot(ri[1] - c[1])).sum();
                    (spread + sense * (c[0] * f[1] - c[1] * f[0] - tau) - got).abs() < 1e-12
                }) {
                    at_contact += 1;
                } else {
                    between += 1;
                }
            }
        }
        // A load on the square where the first Newton step lands exactly on
        // a contact point (by symmetry) that is not the minimum.
        let (r, w) = (&square.contacts[..8], &square.weights[..8]);
        let (f, tau) = ([0.5592085352723886, -0.3474059126262784], -0.01914181903575152);
        let (got, want) = (
            min_psi(r, w, &PolygonLimit::new(r, w), f, tau, 1.0),
            grid_min(r, w, f, tau, 1.0, 50.0 * square.radius),
        );
        assert!((got - want).abs() < 1e-9 * square.radius, "{got} vs grid {want}");
        // Both kinds of minimum were exercised.
        assert!(at_contact > 20 && between > 20, "{at_contact} at contacts, {between} between");
    }

    /// Through `friction::step`, for a turned square: held at 0.97 × its
    /// limit along the direction where the ellipse through pure force and
    /// pure torque is furthest out, broken loose at 1.03 × (the ellipse
    /// would hold both).
    #[test]
    fn turned_square_sticks_inside_and_slips_outside_its_limit() {
        use crate::sim::friction::{self, Coulomb};
        let b = polygon(&[[-0.03, -0.03], [0.03, -0.03], [0.03, 0.03], [-0.03, 0.03]]);
        let (r, w) = (&b.contacts[..b.n_contacts], &b.weights[..b.n_contacts]);
        let mu = Coulomb { kinetic: 0.25 * 9.81, stat: 0.3 * 9.81 };
        // Loads on the unit ellipse (body frame), by polar angle in the
        // (F_x, τ / lever) plane and the force's direction in the body.
        let unit = |p: f64, q: f64| ([p.cos() * q.cos(), p.cos() * q.sin()], p.sin() * b.torsion_lever);
        let radius = |p: f64, q: f64| {
            let (mut lo, mut hi) = (0.0, 1.5);
            for _ in 0..50 {
                let mid = 0.5 * (lo + hi);
                let (f, tau) = unit(p, q);
                if holds(r, w, &b.limit, b.torsion_lever, [mid * f[0], mid * f[1]], mid * tau) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        let (mut worst, mut at) = (1.0, (0.0, 0.0));
        for i in 1..40 {
            for j in 0..16 {
                let (p, q) = (i as f64 * 0.5 * core::f64::consts::PI / 40.0, j as f64 * 0.1);
                let rho = radius(p, q);
                if rho < worst {
                    (worst, at) = (rho, (p, q));
                }
            }
        }
        eprintln!("square: the ellipse reaches {:.1} % beyond the exact limit", (1.0 / worst - 1.0) * 100.0);
        assert!(worst < 0.92, "the ellipse is at most {} % out", (1.0 / worst - 1.0) * 100.0);
        let angle = core::f64::consts::FRAC_PI_8;
        let (sn, cn) = angle.sin_cos();
        for (k, should_stick) in [(0.97, true), (1.03, false)] {
            let (f, tau) = unit(at.0, at.1);
            let m = k * worst * mu.stat;
            // Body-frame force turned to the world; torque per unit mass → α.
            let a = [m * (cn * f[0] - sn * f[1]), m * (sn * f[0] + cn * f[1]), m * tau / b.rho2];
            let (mut v, mut stuck) = ([0.0; 3], true);
            friction::step(&b, angle, [0.0; 3], &mut v, a, 1e-4, mu, &mut stuck);
            assert_eq!(stuck, should_stick, "{k} × the limit");
        }
    }

    /// With no force, a patch spins about its weighted geometric median,
    /// not its centroid, so the pure-torque limit of a thin triangle is
    /// below Σ w_i |r_i|: a torque between the two must break it loose.
    #[test]
    fn pure_torque_limit_is_at_the_geometric_median() {
        let b = polygon(&[[0.0, 0.0], [0.1, 0.0], [0.0, 0.01]]);
        let (r, w) = (&b.contacts[..b.n_contacts], &b.weights[..b.n_contacts]);
        assert!(b.limit.spin < 0.97 * b.torsion_lever, "{} vs {}", b.limit.spin, b.torsion_lever);
        // Independent: Σ w_i |r_i − c| over a fine grid of centres c.
        let grid = (-200..=200)
            .flat_map(|i| (-200..=200).map(move |j| [i as f64 * 2e-4, j as f64 * 2e-4]))
            .map(|c| r.iter().zip(w).map(|(p, wi)| wi * (p[0] - c[0]).hypot(p[1] - c[1])).sum::<f64>())
            .fold(f64::INFINITY, f64::min);
        assert!(
            b.limit.spin <= grid + 1e-12 && grid - b.limit.spin < 1e-6,
            "{} vs grid {grid}",
            b.limit.spin
        );
        let lim = b.limit.spin;
        assert!(holds(r, w, &b.limit, b.torsion_lever, [0.0; 2], 0.999 * lim));
        assert!(!holds(r, w, &b.limit, b.torsion_lever, [0.0; 2], 1.001 * lim));
        assert!(!holds(r, w, &b.limit, b.torsion_lever, [0.0; 2], -1.001 * lim));
    }
}
