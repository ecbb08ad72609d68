//! Ill-conditioned and infeasible requests: bounded K, a truthful report, and
//! a genuinely optimal bounded least-squares answer (not clipping).

mod common;

use common::{random_case, reference_system};
use nalgebra::{DMatrix, DVector};
use upm_solver::field::cycle_force;
use upm_solver::{ForceConstraint, Problem, SolveMethod, Solver, SolverCapacity, SolverParams};

/// Reference: projected gradient on ½‖Ak − b‖², many iterations, no tricks.
fn projected_gradient(a: &DMatrix<f64>, b: &DVector<f64>, k_max: f64) -> DVector<f64> {
    let l = a.clone().singular_values().max().powi(2);
    let mut k = DVector::zeros(a.ncols());
    let mut y = k.clone();
    let mut t = 1.0f64;
    for _ in 0..200_000 {
        let g = a.transpose() * (a * &y - b);
        let k_next = (&y - g / l).map(|v| v.clamp(-k_max, k_max));
        let t_next = (1.0 + (1.0 + 4.0 * t * t).sqrt()) / 2.0;
        y = &k_next + (&k_next - &k) * ((t - 1.0) / t_next);
        k = k_next;
        t = t_next;
    }
    k
}

fn two_close_parts() -> ([[f64; 2]; 9], [ForceConstraint; 2]) {
    let mut centers = [[0.0; 2]; 9];
    for (j, c) in centers.iter_mut().enumerate() {
        let a = j as f64 / 9.0 * std::f64::consts::TAU;
        *c = [1.5 * a.cos(), 1.5 * a.sin()];
    }
    // 1 mm apart, asking for opposite forces.
    let parts = [
        ForceConstraint {
            position: [0.2, 0.1],
            force: Some([0.02, 0.0]),
            shape: upm_solver::PartShape::Point,
        },
        ForceConstraint {
            position: [0.201, 0.1],
            force: Some([-0.02, 0.0]),
            shape: upm_solver::PartShape::Point,
        },
    ];
    (centers, parts)
}

#[test]
fn two_parts_one_millimetre_apart_with_opposite_forces() {
    let (centers, parts) = two_close_parts();
    let k_max = 0.9;
    let problem = Problem { mu_m_g: 0.1, k_max, centers: &centers, parts: &parts, curls: &[], k_bounds: &[] };
    let mut solver = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut out = solver.new_solution();
    solver.solve(&problem, &mut out).expect("solve");
    assert!(out.k().iter().all(|k| k.abs() <= k_max), "k = {:?}", out.k());
    assert!(out.at_bound > 0, "a bound must be active");
    assert!(out.saturated, "opposite forces 1 mm apart are beyond reach");
    assert_eq!(out.method, SolveMethod::BoundedLeastSquares);
    assert!(out.condition > 100.0, "κ = {}", out.condition);
    // Achieved forces are what K really gives, not the request.
    for (a, p) in out.achieved_forces().iter().zip(&parts) {
        let f = cycle_force(out.k(), &centers, 0.1, p.position);
        // Same model, different summation order: equal to rounding.
        let tol = 1e-12 * f[0].hypot(f[1]).max(1e-300);
        assert!((a[0] - f[0]).abs() <= tol && (a[1] - f[1]).abs() <= tol, "{a:?} vs {f:?}");
        assert!((a[0] - p.force.expect("set")[0]).abs() > 1e-3, "the request is not reachable");
    }
    // And the reported residual is the true one.
    let (a, b) = reference_system(&centers, &parts, &[], 0.1);
    let k = DVector::from_column_slice(out.k());
    let r = (&a * &k - &b).norm() * 0.1 / 9.0;
    assert!((r - out.residual).abs() <= 1e-12 * r.max(1.0));
}

#[test]
fn bounded_answer_is_as_good_as_a_converged_projected_gradient() {
    let mut solver = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut out = solver.new_solution();
    let mut checked = 0;
    for seed in 0..12u64 {
        // Close parts and strong forces: infeasible within |k| ≤ 0.5.
        let case = random_case(500 + seed, 4 + seed as usize % 4, 0, 12, 0.02);
        let parts: Vec<_> = case
            .parts
            .iter()
            .map(|p| ForceConstraint { force: p.force.map(|f| [f[0] * 160.0, f[1] * 160.0]), ..*p })
            .collect();
        let k_max = 0.5;
        let problem =
            Problem { mu_m_g: 0.1, k_max, centers: &case.centers, parts: &parts, curls: &[], k_bounds: &[] };
        solver.solve(&problem, &mut out).expect("solve");
        let (a, b) = reference_system(&case.centers, &parts, &[], 0.1);
        let k_ref = projected_gradient(&a, &b, k_max);
        let ours = (&a * DVector::from_column_slice(out.k()) - &b).norm();
        let best = (&a * &k_ref - &b).norm();
        assert!(out.k().iter().all(|k| k.abs() <= k_max));
        assert!(ours <= best * (1.0 + 1e-6) + 1e-9, "seed {seed}: ours {ours} vs reference {best}");
        // Plain clipping of the unconstrained solution is measurably worse.
        let clipped = common::svd_min_norm(&a, &b).map(|v| v.clamp(-k_max, k_max));
        let clip = (&a * &clipped - &b).norm();
        if out.at_bound > 0 && clip > best * 1.01 {
            checked += 1;
        }
    }
    assert!(checked >= 3, "too few cases where bounded LS beats clipping: {checked}");
}

/// Two parts on the same spot with different requests: A has two equal rows
/// pairs, so its rank is short. The unpivoted QR cannot be trusted to show
/// that; the solver must fall back to the pivoted one and report it.
#[test]
fn coincident_parts_report_a_short_rank() {
    let (centers, _) = two_close_parts();
    let parts = [
        ForceConstraint {
            position: [0.2, 0.1],
            force: Some([0.02, 0.0]),
            shape: upm_solver::PartShape::Point,
        },
        ForceConstraint {
            position: [0.2, 0.1],
            force: Some([0.01, 0.005]),
            shape: upm_solver::PartShape::Point,
        },
        ForceConstraint {
            position: [-0.3, 0.2],
            force: Some([0.0, 0.01]),
            shape: upm_solver::PartShape::Point,
        },
    ];
    let problem =
        Problem { mu_m_g: 0.1, k_max: 0.9, centers: &centers, parts: &parts, curls: &[], k_bounds: &[] };
    let mut solver = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut out = solver.new_solution();
    solver.solve(&problem, &mut out).expect("solve");
    assert_eq!(out.rank, 4, "6 rows, 2 of them repeated");
    assert!(out.condition.is_infinite(), "κ = {}", out.condition);
    assert_eq!(out.method, SolveMethod::BoundedLeastSquares);
    assert!(out.k().iter().all(|k| k.abs() <= 0.9));
}
