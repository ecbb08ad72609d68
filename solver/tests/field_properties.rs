//! Property tests of the field model (paper Eq. 8–12).

use proptest::prelude::*;
use upm_solver::field::{cycle_curl, cycle_force, rotation_curl, rotation_divergence, rotation_force};

fn point() -> impl Strategy<Value = [f64; 2]> {
    [-2.0..2.0f64, -2.0..2.0f64]
}

/// Central finite differences of a field at p.
fn jacobian(f: impl Fn([f64; 2]) -> [f64; 2], p: [f64; 2], h: f64) -> [[f64; 2]; 2] {
    let fx1 = f([p[0] + h, p[1]]);
    let fx0 = f([p[0] - h, p[1]]);
    let fy1 = f([p[0], p[1] + h]);
    let fy0 = f([p[0], p[1] - h]);
    [
        [(fx1[0] - fx0[0]) / (2.0 * h), (fy1[0] - fy0[0]) / (2.0 * h)],
        [(fx1[1] - fx0[1]) / (2.0 * h), (fy1[1] - fy0[1]) / (2.0 * h)],
    ]
}

proptest! {
    #[test]
    fn field_is_divergence_free(k in -1.0..1.0f64, c in point(), p in point()) {
        let r = (p[0] - c[0]).hypot(p[1] - c[1]);
        prop_assume!(r > 0.05);
        let h = 1e-5 * r;
        let j = jacobian(|q| rotation_force(k, 0.1, c, q), p, h);
        let fd_div = j[0][0] + j[1][1];
        // Second-order FD error ~ h²·|f'''| ~ 1e-10·μmg/r.
        prop_assert!(fd_div.abs() <= 1e-6 * 0.1 / r, "FD divergence {fd_div}");
        prop_assert!(rotation_divergence(k, 0.1, c, p).abs() <= 1e-12 * 0.1 / (r * r));
    }

    #[test]
    fn curl_matches_finite_difference_curl(k in -1.0..1.0f64, c in point(), p in point()) {
        let r = (p[0] - c[0]).hypot(p[1] - c[1]);
        prop_assume!(r > 0.05);
        let h = 1e-5 * r;
        let j = jacobian(|q| rotation_force(k, 0.1, c, q), p, h);
        let fd_curl = j[1][0] - j[0][1];
        let curl = rotation_curl(k, 0.1, c, p);
        prop_assert!((fd_curl - curl).abs() <= 1e-6 * 0.1 / r, "FD {fd_curl} vs {curl}");
    }

    #[test]
    fn achieved_force_is_the_sum_of_the_individual_fields(
        ks in proptest::collection::vec(-1.0..1.0f64, 1..20),
        seed_c in proptest::collection::vec(point(), 20),
        p in point(),
    ) {
        let centers = &seed_c[..ks.len()];
        prop_assume!(centers.iter().all(|c| (p[0] - c[0]).hypot(p[1] - c[1]) > 1e-3));
        let n = ks.len() as f64;
        let mut sum = [0.0; 2];
        let mut curl = 0.0;
        for (&k, &c) in ks.iter().zip(centers) {
            let f = rotation_force(k, 0.1, c, p);
            sum[0] += f[0] / n;
            sum[1] += f[1] / n;
            curl += rotation_curl(k, 0.1, c, p) / n;
        }
        let f = cycle_force(&ks, centers, 0.1, p);
        prop_assert!((f[0] - sum[0]).abs() <= 1e-15 && (f[1] - sum[1]).abs() <= 1e-15);
        prop_assert!((cycle_curl(&ks, centers, 0.1, p) - curl).abs() <= 1e-9 * curl.abs().max(1.0));
        // |force| of one rotation is exactly |k|·μmg: Coulomb friction's constant magnitude.
        let one = rotation_force(ks[0], 0.1, centers[0], p);
        prop_assert!((one[0].hypot(one[1]) - ks[0].abs() * 0.1).abs() <= 1e-15);
    }
}
