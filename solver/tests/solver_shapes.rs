//! Shaped parts in the solver: a disc or polygon's rows are its patch
//! averages (`wrench_row`), the answer plays what it reports for them, a
//! patch may sit on a center (a point may not), bad shapes are refused by
//! name, and far from every center a shape asks what a point asks.

use upm_solver::{
    CurlConstraint, ForceConstraint, PartShape, Problem, SolveError, Solver, SolverCapacity, SolverParams,
};
use upm_solver::{ShapeError, wrench_row};

const MU_M_G: f64 = 0.1;

fn centers() -> Vec<[f64; 2]> {
    vec![
        [0.05, 0.0],
        [-0.06, 0.04],
        [0.0, -0.08],
        [0.5, 0.4],
        [-0.5, 0.4],
        [0.7, -0.4],
        [-0.7, -0.4],
        [1.0, 0.0],
    ]
}

fn solve(
    parts: &[ForceConstraint],
    curls: &[CurlConstraint],
    centers: &[[f64; 2]],
) -> Result<upm_solver::Solution, SolveError> {
    let problem = Problem { mu_m_g: MU_M_G, k_max: 0.9, centers, parts, curls, k_bounds: &[] };
    let mut s = Solver::new(SolverCapacity::DEFAULT, SolverParams::default());
    let mut out = s.new_solution();
    s.solve(&problem, &mut out).map(|()| out)
}

#[test]
fn a_shaped_part_gets_what_its_patch_rows_say() {
    let disc = PartShape::Disc { radius: 0.03 };
    let tri = PartShape::polygon(&[[-0.02, -0.015], [0.025, -0.01], [0.0, 0.02]]).expect("triangle");
    let c = centers();
    let parts = [
        ForceConstraint { position: [0.0, 0.0], force: Some([0.004, -0.002]), shape: disc },
        ForceConstraint { position: [0.3, -0.2], force: Some([-0.003, 0.001]), shape: tri },
        // Observed only: its achieved force comes from its patch too.
        ForceConstraint { position: [-0.3, 0.1], force: None, shape: disc },
    ];
    let curls = [CurlConstraint { position: [0.0, 0.0], curl: -0.002, shape: disc }];
    let out = solve(&parts, &curls, &c).expect("solves");
    assert!(!out.saturated && out.residual < 1e-12, "{out:?}");
    let n = c.len() as f64;
    for (p, got) in parts.iter().zip(out.achieved_forces()) {
        let mut f = [0.0; 2];
        for (k, &cj) in out.k().iter().zip(&c) {
            let (t, _) = wrench_row(&p.shape, p.position, cj);
            f[0] += k * t[0] * MU_M_G / n;
            f[1] += k * t[1] * MU_M_G / n;
        }
        assert!((f[0] - got[0]).abs() < 1e-12 && (f[1] - got[1]).abs() < 1e-12, "{f:?} vs {got:?}");
        if let Some(want) = p.force {
            assert!((want[0] - got[0]).abs() < 1e-12 && (want[1] - got[1]).abs() < 1e-12);
        }
    }
    let curl: f64 =
        out.k().iter().zip(&c).map(|(k, &cj)| k * wrench_row(&disc, [0.0, 0.0], cj).1).sum::<f64>() * MU_M_G
            / n;
    assert!((curl + 0.002).abs() < 1e-12, "curl {curl}");
}

#[test]
fn a_patch_may_cover_a_center_a_point_may_not() {
    let c = centers();
    let at = |shape| [ForceConstraint { position: [0.05, 0.0], force: Some([0.001, 0.0]), shape }];
    assert_eq!(
        solve(&at(PartShape::Point), &[], &c).err(),
        Some(SolveError::PartOnCenter { part: 0, center: 0 })
    );
    assert!(solve(&at(PartShape::Disc { radius: 0.03 }), &[], &c).is_ok());
}

#[test]
fn bad_shapes_are_refused_by_name() {
    let c = centers();
    let good = ForceConstraint { position: [0.2, 0.1], force: Some([0.001, 0.0]), shape: PartShape::Point };
    let bad = ForceConstraint { shape: PartShape::Disc { radius: -1.0 }, ..good };
    let e = solve(&[good, bad], &[], &c).expect_err("refused");
    assert_eq!(e, SolveError::PartShape { part: 1, error: ShapeError::Radius });
    assert_eq!(e.to_string(), "parts[1].shape: radius must be a finite number ≥ 0.0001 m");
    let star = PartShape::Polygon {
        vertices: [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0], [0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]],
        count: 4,
    };
    let curl = CurlConstraint { position: [0.2, 0.1], curl: 0.001, shape: star };
    let e = solve(&[good], &[curl], &c).expect_err("refused");
    assert_eq!(e, SolveError::CurlShape { curl: 0, error: ShapeError::NotConvex });
}

#[test]
fn far_from_every_center_a_small_shape_asks_what_a_point_asks() {
    let c = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]];
    let k = |shape| {
        let parts = [ForceConstraint { position: [0.1, 0.05], force: Some([0.004, 0.002]), shape }];
        solve(&parts, &[], &c).expect("solves").k().to_vec()
    };
    let (point, disc) = (k(PartShape::Point), k(PartShape::Disc { radius: 0.005 }));
    for (a, b) in point.iter().zip(&disc) {
        assert!((a - b).abs() < 1e-4, "{point:?} vs {disc:?}");
    }
}
