//! The paper's worked examples (§3.1, §3.3): any correct solver reproduces
//! their K vectors to the printed precision.

use upm_solver::{CurlConstraint, ForceConstraint, Problem, Solver, SolverCapacity, SolverParams};

fn solver() -> Solver {
    Solver::new(SolverCapacity::DEFAULT, SolverParams::default())
}

#[test]
fn section_3_1_four_corners_two_parts() {
    let centers = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]];
    let parts = [
        ForceConstraint {
            position: [0.5, 0.0],
            force: Some([0.01, 0.01]),
            shape: upm_solver::PartShape::Point,
        },
        ForceConstraint {
            position: [-0.75, 0.25],
            force: Some([-0.01, 0.0]),
            shape: upm_solver::PartShape::Point,
        },
    ];
    let problem =
        Problem { mu_m_g: 0.1, k_max: 1.0, centers: &centers, parts: &parts, curls: &[], k_bounds: &[] };
    let mut s = solver();
    let mut out = s.new_solution();
    s.solve(&problem, &mut out).expect("solve");
    let expected = [0.58, -0.39, 0.48, -0.095];
    for (k, e) in out.k().iter().zip(expected) {
        assert!((k - e).abs() <= 0.006, "k = {:?}, paper {expected:?}", out.k());
    }
    assert!(!out.saturated);
    assert_eq!(out.rank, 4);
    assert!(out.residual < 1e-12, "residual {}", out.residual);
    // Achieved forces equal the requests (the system is square and consistent).
    for (a, p) in out.achieved_forces().iter().zip(&parts) {
        let f = p.force.expect("constrained");
        assert!((a[0] - f[0]).abs() < 1e-12 && (a[1] - f[1]).abs() < 1e-12);
    }
    // ρ from the formula: C3 and C1 lead (|k|/min distance); the paper's
    // printed priorities do not follow from its own formula.
    let order: Vec<u16> = out.order().to_vec();
    assert_eq!(order.len(), 4);
    for w in order.windows(2) {
        assert!(out.priority()[w[0] as usize] >= out.priority()[w[1] as usize]);
    }
}

#[test]
fn section_3_3_zero_force_with_curl() {
    let centers = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5]];
    let parts = [ForceConstraint {
        position: [0.5, 0.0],
        force: Some([0.0, 0.0]),
        shape: upm_solver::PartShape::Point,
    }];
    let curls = [CurlConstraint { position: [0.5, 0.0], curl: -0.05, shape: upm_solver::PartShape::Point }];
    let problem =
        Problem { mu_m_g: 0.1, k_max: 1.0, centers: &centers, parts: &parts, curls: &curls, k_bounds: &[] };
    let mut s = solver();
    let mut out = s.new_solution();
    s.solve(&problem, &mut out).expect("solve");
    let expected = [-0.59, -0.27, -0.53];
    for (k, e) in out.k().iter().zip(expected) {
        assert!((k - e).abs() <= 0.006, "k = {:?}, paper {expected:?}", out.k());
    }
    assert!((out.achieved_curls()[0] + 0.05).abs() < 1e-12);
}
