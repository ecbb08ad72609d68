//! Friction of a uniform disc: uniform pressure over the whole face,
//! integrated exactly once per process and tabulated, kinetic friction and
//! the static limit curve (the same integrals at μ_s, by load direction).
//!
//! For a relative twist (v, ω) of plate over part, the friction on a disc of
//! radius R depends only on the direction of (v, ωR). With n = |(v, ωR)| and
//! t² = (ωR)²/n²:
//!
//!   F/m = μ_k g · A(t²) · v / n,    τ/m = μ_k g · R · B(t²) · ωR / n.
//!
//! A and B are universal. A(0) = 1 (pure sliding: μ_k m g), B(1) = 2/3 (pure
//! spin: ⅔ μ_k m g R), and A(1) = 1, B(0) = 1/4 are the linear responses at
//! the two ends. Each ring of the face contributes complete elliptic
//! integrals (evaluated by the AGM); the integral over the radius is
//! tanh-sinh quadrature, split at the ring through the instantaneous centre,
//! where the ring integrals are not smooth. One evaluation then costs one
//! square root, two divisions and a table lookup, instead of a sum over
//! contact points.

use core::f64::consts::PI;
use std::sync::OnceLock;

/// Table intervals over t² ∈ [0, 1] (and over z ∈ [0, 1] for the limit).
const INTERVALS: usize = 1024;

/// The disc's friction tables, shared by every disc of every size.
#[derive(Debug)]
pub(crate) struct Table {
    /// (A, B) at t² = i / INTERVALS.
    kinetic: [[f64; 2]; INTERVALS + 1],
    /// The static limit curve in normalised (f̂, τ̂) = (F, τ/R) / (μ m g):
    /// its squared radius ρ² at z = τ̂² / (f̂² + τ̂²) = i / INTERVALS.
    limit: [f64; INTERVALS + 1],
}

static TABLE: OnceLock<Table> = OnceLock::new();

/// The tables, built on first use (about 10 ms; call it at construction so
/// that the hot path only reads them).
pub(crate) fn table() -> &'static Table {
    TABLE.get_or_init(build)
}

/// Row index and fraction of `x` in [0, 1] (NaN gives a finite row and a
/// NaN fraction).
#[inline(always)]
fn row(x: f64) -> (usize, f64) {
    let x = x * INTERVALS as f64;
    let row = x.floor().min((INTERVALS - 1) as f64);
    // The row's index from the bits of row + 2⁵² (exact for integers below
    // 2⁵²): no float-to-integer conversion, which lanes cannot vectorise.
    let i = ((row + TWO_POW_52).to_bits() as usize) & (INTERVALS - 1);
    (i, x - row)
}

/// (A(t²), B(t²)) by linear interpolation; `t2` in [0, 1] (NaN gives a
/// NaN result).
#[inline(always)]
pub(crate) fn lookup(table: &Table, t2: f64) -> [f64; 2] {
    let (i, f) = row(t2);
    let (lo, hi) = (table.kinetic[i], table.kinetic[i + 1]);
    [lo[0] + f * (hi[0] - lo[0]), lo[1] + f * (hi[1] - lo[1])]
}

/// ρ²(z) of the static limit curve by linear interpolation.
#[inline(always)]
pub(crate) fn limit_lookup(table: &Table, z: f64) -> f64 {
    let (i, f) = row(z);
    let (lo, hi) = (table.limit[i], table.limit[i + 1]);
    lo + f * (hi - lo)
}

const TWO_POW_52: f64 = 4_503_599_627_370_496.0;
const _: () = assert!(INTERVALS.is_power_of_two());

/// Static friction of a disc of radius `r` and I/m `rho2` moving with the
/// plate, whose twist acceleration there is `a`, with μ_s g = `cs`: the
/// normalised squared load n² and its direction z (the inputs of
/// [`limit_lookup`] and [`sticks_with`]).
#[inline(always)]
pub(crate) fn static_args(r: f64, rho2: f64, a: [f64; 3], cs: f64) -> (f64, f64) {
    let tq = rho2 * a[2] / r;
    let (f2, t2) = (a[0] * a[0] + a[1] * a[1], tq * tq);
    let n2 = (f2 + t2) / (cs * cs);
    (n2, t2 / (f2 + t2))
}

/// Inside the limit curve (ρ² from [`limit_lookup`])? No load at all sticks
/// (its direction is NaN).
#[inline(always)]
pub(crate) fn sticks_with(n2: f64, rho2_limit: f64) -> bool {
    (n2 <= rho2_limit) | (n2 == 0.0)
}

/// Can static friction hold the disc on a plate accelerating (twist `a`)?
/// The true limit of a uniformly pressed face: the boundary is what kinetic
/// friction gives at μ_s, over every direction of sliding.
#[inline(always)]
pub(crate) fn sticks(table: &Table, r: f64, rho2: f64, a: [f64; 3], cs: f64) -> bool {
    let (n2, z) = static_args(r, rho2, a, cs);
    sticks_with(n2, limit_lookup(table, z))
}

/// Kinetic friction per unit mass (force, and torque over I) on a disc of
/// radius `r` and I/m `rho2` for relative twist `xi`; zero at relative rest.
#[inline(always)]
pub(crate) fn kinetic(table: &Table, r: f64, rho2: f64, xi: [f64; 3], ck: f64) -> [f64; 3] {
    let (n2, t2) = kinetic_args(r, xi);
    kinetic_finish(r, rho2, xi, n2, lookup(table, t2), ck)
}

/// [`kinetic`] in two branch-free halves around the table lookup, so that
/// the disc lanes can vectorise the halves: this one gives (n², t²).
#[inline(always)]
pub(crate) fn kinetic_args(r: f64, xi: [f64; 3]) -> (f64, f64) {
    let q = xi[2] * r;
    let n2 = xi[0] * xi[0] + xi[1] * xi[1] + q * q;
    // At n² = 0, t² is NaN: the lookup reads the last row, and the result
    // is masked in `kinetic_finish`.
    (n2, q * q / n2)
}

#[inline(always)]
pub(crate) fn kinetic_finish(
    r: f64,
    rho2: f64,
    xi: [f64; 3],
    n2: f64,
    [ca, cb]: [f64; 2],
    ck: f64,
) -> [f64; 3] {
    let q = xi[2] * r;
    let k = ck / n2.sqrt();
    let moving = n2 > 0.0;
    [
        if moving { k * ca * xi[0] } else { 0.0 },
        if moving { k * ca * xi[1] } else { 0.0 },
        if moving { k * cb * r * q / rho2 } else { 0.0 },
    ]
}

fn build() -> Table {
    let nodes = TanhSinh::new();
    let mut t = Table { kinetic: [[0.0; 2]; INTERVALS + 1], limit: [0.0; INTERVALS + 1] };
    for (i, row) in t.kinetic.iter_mut().enumerate() {
        *row = coefficients_with(&nodes, i as f64 / INTERVALS as f64);
    }
    for i in 0..=INTERVALS {
        t.limit[i] = limit_at(&t, i as f64 / INTERVALS as f64);
    }
    t
}

/// The limit curve's point for sliding direction t² = u, normalised:
/// (f̂, τ̂) = (A·√(1−u), B·√u), and its (ρ², z).
fn limit_point(t: &Table, u: f64) -> (f64, f64) {
    let [a, b] = lookup(t, u);
    let (f2, t2) = (a * a * (1.0 - u), b * b * u);
    (f2 + t2, t2 / (f2 + t2))
}

/// ρ² where the limit curve has direction z, by bisection over the sliding
/// direction u (z grows with u: the curve is convex and its normal turns
/// with the sliding direction).
fn limit_at(t: &Table, z: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if limit_point(t, mid).1 < z {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    limit_point(t, 0.5 * (lo + hi)).0
}

/// (A, B) at t² by quadrature; the two ends are the linear-response limits.
#[cfg(test)]
fn coefficients(t2: f64) -> [f64; 2] {
    coefficients_with(&TanhSinh::new(), t2)
}

fn coefficients_with(nodes: &TanhSinh, t2: f64) -> [f64; 2] {
    if t2 <= 0.0 {
        return [1.0, 0.25];
    }
    if t2 >= 1.0 {
        return [1.0, 2.0 / 3.0];
    }
    let (s, q) = ((1.0 - t2).sqrt(), t2.sqrt());
    // Unit radius, v = s along x, ωR = q; ring integrals per unit angle
    // weight: I_x(r) = 2[(s − qr)K + (s + qr)E]/s, I_τ(r) = 2[(s + qr)E −
    // (s − qr)K]/q, with modulus k² = 4sqr/(s + qr)². Here the 1/s and 1/q
    // are folded into A = F/s and B = τ/q.
    let ring = |r: f64| {
        let (minus, plus) = (s - q * r, s + q * r);
        let (k, e) = elliptic_ke(minus.abs() / plus);
        [(minus * k + plus * e) * r, (plus * e - minus * k) * r]
    };
    let r_star = s / q;
    let mut sum = nodes.integrate(&ring, 0.0, r_star.min(1.0));
    if r_star < 1.0 {
        let outer = nodes.integrate(&ring, r_star, 1.0);
        sum = [sum[0] + outer[0], sum[1] + outer[1]];
    }
    // F = (1/π) ∫ I_x r dr, so A = F/s = (2/π) ∫ ring_x dr / s²; B likewise.
    [2.0 / PI * sum[0] / (s * s), 2.0 / PI * sum[1] / (q * q)]
}

/// Complete elliptic integrals K(k) and E(k), given the complementary
/// modulus k' = √(1 − k²) (exact here, with no cancellation near k = 1),
/// by the arithmetic–geometric mean.
fn elliptic_ke(k_prime: f64) -> (f64, f64) {
    let (mut a, mut b) = (1.0f64, k_prime);
    // Σ 2^(n−1) c_n², with c_0² = k² = 1 − k'².
    let mut sum = 0.5 * (1.0 - k_prime) * (1.0 + k_prime);
    let mut pow = 0.5;
    for _ in 0..64 {
        let c = 0.5 * (a - b);
        if c <= f64::EPSILON * a {
            break;
        }
        let next = [0.5 * (a + b), (a * b).sqrt()];
        pow *= 2.0;
        sum += pow * c * c;
        [a, b] = next;
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// Tanh-sinh quadrature: nodes and weights on (−1, 1), computed once.
/// Exact to rounding for integrands analytic inside the interval, even with
/// integrable singularities at its ends.
struct TanhSinh {
    /// (x, w), x = tanh(π/2 · sinh t) for t = j·STEP, |t| ≤ 3.
    nodes: [(f64, f64); 2 * Self::LEVELS + 1],
}

impl TanhSinh {
    const STEP: f64 = 1.0 / 16.0;
    const LEVELS: usize = 48;

    fn new() -> Self {
        let nodes = core::array::from_fn(|i| {
            let t = (i as f64 - Self::LEVELS as f64) * Self::STEP;
            let u = 0.5 * PI * t.sinh();
            (u.tanh(), Self::STEP * 0.5 * PI * t.cosh() / (u.cosh() * u.cosh()))
        });
        Self { nodes }
    }

    /// ∫ f over [lo, hi].
    fn integrate(&self, f: &impl Fn(f64) -> [f64; 2], lo: f64, hi: f64) -> [f64; 2] {
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        let mut sum = [0.0; 2];
        for &(xu, wu) in &self.nodes {
            let x = mid + half * xu;
            // The ends themselves are never sampled (the ring integrals are
            // infinite times zero there); their weight is below rounding.
            if x <= lo || x >= hi {
                continue;
            }
            let v = f(x);
            sum[0] += half * wu * v[0];
            sum[1] += half * wu * v[1];
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: midpoint rule over a fine polar grid of the unit disc.
    fn brute(t2: f64) -> [f64; 2] {
        let (s, q) = ((1.0 - t2).sqrt(), t2.sqrt());
        let (nr, nt) = (800, 1600);
        let (mut fx, mut tau) = (0.0, 0.0);
        for i in 0..nr {
            let r = (i as f64 + 0.5) / nr as f64;
            for j in 0..nt {
                let th = (j as f64 + 0.5) / nt as f64 * 2.0 * PI;
                let (y, x) = (r * th.sin(), r * th.cos());
                let (wx, wy) = (s - q * y, q * x);
                let n = wx.hypot(wy);
                let da = r / nr as f64 * 2.0 * PI / nt as f64 / PI;
                fx += wx / n * da;
                tau += (x * wy - y * wx) / n * da;
            }
        }
        [fx / s, tau / q]
    }

    #[test]
    fn quadrature_matches_a_brute_force_sum_over_the_face() {
        for t2 in [0.05, 0.3, 0.5, 0.62, 0.9] {
            let (exact, b) = (coefficients(t2), brute(t2));
            for k in 0..2 {
                assert!((exact[k] - b[k]).abs() < 2e-6, "t² = {t2}: {exact:?} vs brute {b:?}");
            }
        }
    }

    #[test]
    fn ends_are_the_linear_responses_and_the_table_is_continuous() {
        let t = table();
        assert!((coefficients(1e-6)[0] - 1.0).abs() < 1e-5);
        assert!((coefficients(1e-6)[1] - 0.25).abs() < 1e-5);
        assert!((coefficients(1.0 - 1e-6)[0] - 1.0).abs() < 1e-5);
        assert!((coefficients(1.0 - 1e-6)[1] - 2.0 / 3.0).abs() < 1e-5);
        for w in t.kinetic.windows(2) {
            assert!(w[0].iter().chain(&w[1]).all(|v| v.is_finite() && *v > 0.0));
            assert!((w[0][0] - w[1][0]).abs() < 2e-3 && (w[0][1] - w[1][1]).abs() < 2e-3, "{w:?}");
        }
    }

    #[test]
    fn lookup_interpolates_between_rows() {
        let t = table();
        // Every row midpoint (worst at the kink t² = 1/2, where the
        // instantaneous centre reaches the rim), and the two ends.
        let mids = (0..INTERVALS).map(|i| (i as f64 + 0.5) / INTERVALS as f64);
        for t2 in mids.chain([0.0, 1.0]) {
            let (got, want) = (lookup(t, t2), coefficients(t2));
            assert!(
                (got[0] - want[0]).abs() < 5e-6 && (got[1] - want[1]).abs() < 5e-6,
                "{t2}: {got:?} {want:?}"
            );
        }
    }

    /// The limit curve is the boundary of the set of forces static friction
    /// can supply: a load is inside iff, for every sliding direction d,
    /// its power along d is at most that of kinetic friction (at μ_s) along
    /// d (maximum dissipation). Checked over 1 024 load directions, 0.2 %
    /// inside and outside the tabulated curve, against 4 096 sliding
    /// directions; and at the ends, pure force (μ_s m g) and pure torque
    /// (⅔ μ_s m g R).
    #[test]
    fn limit_curve_is_where_kinetic_friction_stops_dominating() {
        let t = table();
        assert!((t.limit[0] - 1.0).abs() < 1e-12 && (t.limit[INTERVALS] - 4.0 / 9.0).abs() < 1e-12);
        // Worst excess of the load's power over friction's, over sliding
        // directions u = t².
        let excess = |f: f64, tau: f64| {
            (0..=4096)
                .map(|j| {
                    let u = j as f64 / 4096.0;
                    let [a, b] = lookup(t, u);
                    f * (1.0 - u).sqrt() + tau * u.sqrt() - (a * (1.0 - u) + b * u)
                })
                .fold(f64::NEG_INFINITY, f64::max)
        };
        for i in 0..1024 {
            let phi = (i as f64 + 0.5) / 1024.0 * 0.5 * PI;
            let (f, tau) = (phi.cos(), phi.sin());
            let z = tau * tau;
            let rho = limit_lookup(t, z).sqrt();
            assert!(excess(0.998 * rho * f, 0.998 * rho * tau) < 0.0, "inside at z = {z}");
            assert!(excess(1.002 * rho * f, 1.002 * rho * tau) > 0.0, "outside at z = {z}");
            // `sticks` reads the same curve, for any radius.
            let (r, cs) = (0.03, 2.943);
            let rho2 = 0.5 * r * r;
            let a = |k: f64| [k * rho * f * cs, 0.0, k * rho * tau * cs * r / rho2];
            assert!(sticks(t, r, rho2, a(0.998), cs) && !sticks(t, r, rho2, a(1.002), cs), "z = {z}");
        }
        assert!(sticks(t, 0.03, 4.5e-4, [0.0; 3], 2.943));
    }
}
