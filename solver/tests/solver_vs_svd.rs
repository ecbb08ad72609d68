//! On seeded random well-conditioned systems, K is the minimum-norm solution
//! of an independent SVD (nalgebra), and κ₂ matches the SVD's.

mod common;

use common::{random_case, reference_system, svd_condition, svd_min_norm};
use upm_solver::{Problem, SolveMethod, Solver, SolverCapacity, SolverParams};

fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt();
    let den: f64 = b.iter().map(|y| y * y).sum::<f64>().sqrt().max(1e-300);
    num / den
}

#[test]
fn random_underdetermined_systems_match_svd_min_norm() {
    let mut solver = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut out = solver.new_solution();
    let mut checked = 0;
    let mut worst_ratio = f64::INFINITY;
    for seed in 0..200u64 {
        let parts = 1 + (seed as usize % 10);
        let curls = seed as usize % 3;
        let rows = 2 * parts + curls;
        let centers = rows + 2 + (seed as usize % 12);
        let case = random_case(seed, parts, curls, centers, 0.25);
        let (a, b) = reference_system(&case.centers, &case.parts, &case.curls, 0.1);
        let cond = svd_condition(&a);
        if cond > 1e4 {
            continue; // this test is about well-conditioned systems
        }
        let k_ref = svd_min_norm(&a, &b);
        let problem = Problem {
            mu_m_g: 0.1,
            k_max: 1.0,
            centers: &case.centers,
            parts: &case.parts,
            curls: &case.curls,
            k_bounds: &[],
        };
        solver.solve(&problem, &mut out).expect("solve");
        if k_ref.amax() > 1.0 {
            assert_eq!(out.method, SolveMethod::BoundedLeastSquares, "seed {seed}");
            continue;
        }
        assert_eq!(out.method, SolveMethod::Exact, "seed {seed}");
        let d = rel_diff(out.k(), k_ref.as_slice());
        assert!(d <= 1e-9, "seed {seed}: relative difference {d:e}");
        assert_eq!(out.rank, rows);
        // The estimate is a lower bound from 12 power/inverse iterations;
        // it only gates the exact path, so a factor of 2 is plenty.
        assert!(
            out.condition <= cond * (1.0 + 1e-9) && out.condition >= 0.5 * cond,
            "seed {seed}: κ estimate {} vs svd {cond}",
            out.condition
        );
        worst_ratio = worst_ratio.min(out.condition / cond);
        assert!(!out.saturated);
        checked += 1;
    }
    assert!(checked >= 100, "only {checked} well-conditioned cases were checked");
    println!("checked {checked} cases; worst κ estimate / svd κ = {worst_ratio:.4}");
}

#[test]
fn overdetermined_systems_give_the_least_squares_solution() {
    let mut solver = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut out = solver.new_solution();
    for seed in 0..50u64 {
        // 6 parts (12 rows) but only 8 centers: least squares, not exact.
        let case = random_case(1000 + seed, 6, 0, 8, 0.3);
        let (a, b) = reference_system(&case.centers, &case.parts, &case.curls, 0.1);
        let k_ref = svd_min_norm(&a, &b);
        let problem = Problem {
            mu_m_g: 0.1,
            k_max: 1.0,
            centers: &case.centers,
            parts: &case.parts,
            curls: &[],
            k_bounds: &[],
        };
        solver.solve(&problem, &mut out).expect("solve");
        if k_ref.amax() > 1.0 || svd_condition(&a) > 1e4 {
            continue;
        }
        assert_eq!(out.method, SolveMethod::Exact);
        let d = rel_diff(out.k(), k_ref.as_slice());
        assert!(d <= 1e-9, "seed {seed}: relative difference {d:e}");
        let r_ref = (&a * &k_ref - &b).norm() * 0.1 / case.centers.len() as f64;
        assert!((out.residual - r_ref).abs() <= 1e-12 + 1e-9 * r_ref, "{} vs {r_ref}", out.residual);
    }
}

#[test]
fn same_input_gives_bit_identical_output() {
    let case = random_case(7, 8, 2, 30, 0.2);
    let problem = Problem {
        mu_m_g: 0.1,
        k_max: 0.9,
        centers: &case.centers,
        parts: &case.parts,
        curls: &case.curls,
        k_bounds: &[],
    };
    let mut s1 = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut s2 = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let (mut a, mut b) = (s1.new_solution(), s2.new_solution());
    s1.solve(&problem, &mut a).expect("solve");
    // Dirty the second solver's buffers with another problem first.
    let other = random_case(8, 30, 4, 100, 0.05);
    let p2 = Problem {
        mu_m_g: 0.2,
        k_max: 0.5,
        centers: &other.centers,
        parts: &other.parts,
        curls: &other.curls,
        k_bounds: &[],
    };
    s2.solve(&p2, &mut b).expect("solve");
    s2.solve(&problem, &mut b).expect("solve");
    let bits = |s: &upm_solver::Solution| s.k().iter().map(|k| k.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(a.order(), b.order());
    assert_eq!(a.residual.to_bits(), b.residual.to_bits());
}
