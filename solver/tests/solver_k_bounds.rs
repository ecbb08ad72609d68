//! Per-center bounds on |k| (`Problem::k_bounds`, what each rotation can
//! play on the rig): every path keeps each center within its own bound, the
//! bounded answer is the box optimum (against an exhaustive enumeration on
//! an independently built A), reported forces are the played field, and
//! equal bounds change nothing, bit for bit.

mod common;

use common::{random_case, reference_system};
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use upm_solver::{Problem, SolveError, Solver, SolverCapacity, SolverParams};

const MU_M_G: f64 = 0.1;

fn solver(cycle_slots: usize) -> Solver {
    Solver::new(SolverCapacity::DEFAULT, SolverParams { cycle_slots, ..SolverParams::default() })
}

fn random_bounds(seed: u64, n: usize) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    (0..n).map(|_| rng.random_range(0.15..1.0)).collect()
}

fn saturating(seed: u64, parts: usize, curls: usize, n: usize, gain: f64) -> common::RandomCase {
    let mut case = random_case(seed, parts, curls, n, 0.05);
    for p in &mut case.parts {
        p.force = p.force.map(|f| [f[0] * gain, f[1] * gain]);
    }
    for q in &mut case.curls {
        q.curl *= gain;
    }
    case
}

#[test]
fn every_center_stays_within_its_own_bound_and_plays_what_is_reported() {
    for slots in [0, 24] {
        for seed in 0..60u64 {
            let n = 6 + (seed as usize % 20);
            let case =
                saturating(seed, 1 + seed as usize % 6, seed as usize % 2, n, 50.0 + 20.0 * seed as f64);
            let bounds = random_bounds(seed, n);
            let k_max = 0.8;
            let problem = Problem {
                mu_m_g: MU_M_G,
                k_max,
                centers: &case.centers,
                parts: &case.parts,
                curls: &case.curls,
                k_bounds: &bounds,
            };
            let mut s = solver(slots);
            let mut out = s.new_solution();
            s.solve(&problem, &mut out).expect("solves");
            for (j, (&k, &u)) in out.k().iter().zip(&bounds).enumerate() {
                assert!(
                    k.abs() <= u.min(k_max) * (1.0 + 1e-12),
                    "slots {slots} seed {seed}: k[{j}] = {k} > {u}"
                );
            }
            if slots == 0 {
                // The achieved forces are the independent A·k of Eq. 10.
                let (a, _) = reference_system(&case.centers, &case.parts, &case.curls, MU_M_G);
                let f = &a * DVector::from_column_slice(out.k()) * (MU_M_G / n as f64);
                let mf = out.achieved_forces().len();
                for (i, got) in out.achieved_forces().iter().enumerate() {
                    for (axis, &g) in got.iter().enumerate() {
                        let want = f[axis * mf + i];
                        assert!((g - want).abs() <= 1e-9 * MU_M_G, "seed {seed}: {g} vs {want}");
                    }
                }
            }
        }
    }
}

/// min ½‖A k − b‖² over |k_j| ≤ u_j by enumerating the 3ⁿ active sets
/// (free blocks by nalgebra's SVD, no regularisation).
fn enumerate_optimum(a: &DMatrix<f64>, b: &DVector<f64>, u: &[f64]) -> f64 {
    let (m, n) = a.shape();
    let mut best = f64::INFINITY;
    for mut code in 0..3usize.pow(n as u32) {
        let mut k = vec![0.0; n];
        let mut free = Vec::new();
        for j in 0..n {
            match code % 3 {
                0 => free.push(j),
                1 => k[j] = u[j],
                _ => k[j] = -u[j],
            }
            code /= 3;
        }
        let mut r = b.clone();
        for j in (0..n).filter(|&j| k[j] != 0.0) {
            r -= a.column(j) * k[j];
        }
        if !free.is_empty() {
            let af = DMatrix::from_fn(m, free.len(), |i, c| a[(i, free[c])]);
            let kf = af.svd(true, true).solve(&r, 1e-14).expect("svd");
            if free.iter().zip(kf.iter()).any(|(&j, v)| v.abs() > u[j] * (1.0 + 1e-12)) {
                continue;
            }
            for (c, &j) in free.iter().enumerate() {
                k[j] = kf[c];
            }
        }
        let res = a * DVector::from_column_slice(&k) - b;
        best = best.min(0.5 * res.norm_squared());
    }
    best
}

#[test]
fn the_bounded_answer_is_the_box_optimum_with_per_center_bounds() {
    let mut checked = 0;
    for seed in 0..150u64 {
        let n = 2 + seed as usize % 5;
        let case = saturating(seed, 1 + seed as usize % 3, seed as usize % 2, n, 100.0 + 7.0 * seed as f64);
        let bounds = random_bounds(seed, n);
        let problem = Problem {
            mu_m_g: MU_M_G,
            k_max: 1.0,
            centers: &case.centers,
            parts: &case.parts,
            curls: &case.curls,
            k_bounds: &bounds,
        };
        let mut s = solver(0);
        let mut out = s.new_solution();
        s.solve(&problem, &mut out).expect("solves");
        let (a, b) = reference_system(&case.centers, &case.parts, &case.curls, MU_M_G);
        let best = enumerate_optimum(&a, &b, &bounds);
        let res = &a * DVector::from_column_slice(out.k()) - &b;
        let got = 0.5 * res.norm_squared();
        // Within the regularisation's reach of the optimum (ε = 1e-9 ‖A‖²/n).
        assert!(got <= best * (1.0 + 1e-6) + 1e-9 * b.norm_squared(), "seed {seed}: {got} vs optimum {best}");
        checked += usize::from(out.at_bound > 0);
    }
    assert!(checked > 100, "only {checked} of 150 cases had a bound active");
}

#[test]
fn a_weak_center_is_held_at_its_own_bound() {
    // One part asking far more than the cycle gives: the center nearest it
    // is the strongest lever, and its bound (not k_max) is what binds.
    let centers = [[-0.3, 0.0], [0.3, 0.0], [0.0, 0.4], [0.0, -0.4]];
    let parts = [upm_solver::ForceConstraint {
        position: [0.0, 0.05],
        force: Some([0.5, 0.0]),
        shape: upm_solver::PartShape::Point,
    }];
    let bounds = [0.9, 0.9, 0.3, 0.9];
    let problem = Problem {
        mu_m_g: MU_M_G,
        k_max: 0.9,
        centers: &centers,
        parts: &parts,
        curls: &[],
        k_bounds: &bounds,
    };
    let mut s = solver(0);
    let mut out = s.new_solution();
    s.solve(&problem, &mut out).expect("solves");
    assert!(out.saturated && out.at_bound >= 1, "{out:?}");
    assert!((out.k()[2].abs() - 0.3).abs() <= 1e-12, "k = {:?}", out.k());
}

#[test]
fn bounds_no_tighter_than_k_max_change_nothing() {
    for slots in [0, 24] {
        for seed in 0..20u64 {
            let n = 8 + seed as usize % 16;
            let case = saturating(seed, 1 + seed as usize % 8, 0, n, 30.0 * (1 + seed) as f64);
            let loose: Vec<f64> = (0..n).map(|j| if j % 2 == 0 { 0.7 } else { 1.0 }).collect();
            let run = |bounds: &[f64]| {
                let problem = Problem {
                    mu_m_g: MU_M_G,
                    k_max: 0.7,
                    centers: &case.centers,
                    parts: &case.parts,
                    curls: &[],
                    k_bounds: bounds,
                };
                let mut s = solver(slots);
                let mut out = s.new_solution();
                s.solve(&problem, &mut out).expect("solves");
                (out.k().iter().map(|k| k.to_bits()).collect::<Vec<_>>(), out.counts().to_vec())
            };
            assert_eq!(run(&[]), run(&loose), "slots {slots} seed {seed}");
        }
    }
}

#[test]
fn bad_bounds_are_refused_by_name() {
    let case = random_case(1, 2, 0, 5, 0.05);
    let refuse = |bounds: &[f64]| {
        let problem = Problem {
            mu_m_g: MU_M_G,
            k_max: 0.9,
            centers: &case.centers,
            parts: &case.parts,
            curls: &[],
            k_bounds: bounds,
        };
        let mut s = solver(0);
        let mut out = s.new_solution();
        s.solve(&problem, &mut out).expect_err("refused")
    };
    assert_eq!(refuse(&[0.5; 4]), SolveError::KBoundsLength { given: 4, centers: 5 });
    for (bad, center) in [(f64::NAN, 0), (0.0, 1), (-0.2, 2), (1.5, 3), (f64::INFINITY, 4)] {
        let mut b = [0.5; 5];
        b[center] = bad;
        let e = refuse(&b);
        assert_eq!(e, SolveError::InvalidKBound { center });
        assert_eq!(e.to_string(), format!("k_bounds[{center}]: must be a finite number in (0, 1]"));
    }
}
