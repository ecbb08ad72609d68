//! `saturated` means what its name says: a bound keeps the request from
//! being met. A request met with a bound active counts in `at_bound` alone;
//! one beyond reach is saturated; a zero request is neither. The reach
//! itself (`solver::max_force_*`) is checked against the solver: the most
//! it says is met, 5 % more is saturated.

use upm_solver::{ForceConstraint, PartShape, Problem, Solution, Solver, SolverCapacity, SolverParams};
use upm_solver::{SATURATION_TOLERANCE, max_force_at, max_force_in};

const MU_M_G: f64 = 0.1;
const CORNERS: [[f64; 2]; 4] = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]];

fn solve(
    centers: &[[f64; 2]],
    bounds: &[f64],
    cycle_slots: usize,
    at: [f64; 2],
    force: [f64; 2],
) -> Solution {
    let mut s = Solver::new(SolverCapacity::DEFAULT, SolverParams { cycle_slots, ..SolverParams::default() });
    let parts = [ForceConstraint { position: at, force: Some(force), shape: PartShape::Point }];
    let k_max = bounds.iter().fold(0.0, |a: f64, &b| a.max(b));
    let problem = Problem { mu_m_g: MU_M_G, k_max, centers, parts: &parts, curls: &[], k_bounds: bounds };
    let mut out = s.new_solution();
    s.solve(&problem, &mut out).expect("solves");
    out
}

fn scaled(d: [f64; 2], f: f64) -> [f64; 2] {
    [d[0] * f, d[1] * f]
}

fn met(out: &Solution, force: [f64; 2]) -> bool {
    out.residual <= SATURATION_TOLERANCE * force[0].hypot(force[1])
}

#[test]
fn a_request_met_with_a_bound_active_is_not_saturated() {
    let bounds = [0.9; 4];
    let p = [0.5, 0.0];
    let (most, d) = max_force_at(&CORNERS, &bounds, MU_M_G, 0, 0.0, p);
    // Near the farthest vertex only K near the box's corner gives the force:
    // the minimum-norm K leaves the box and bounded least squares meets it.
    let force = scaled(d, 0.98 * most);
    let out = solve(&CORNERS, &bounds, 0, p, force);
    assert!(out.at_bound >= 1, "a bound must be active: {out:?}");
    assert!(!out.saturated && out.residual <= 1e-9 * 0.98 * most, "met, so not saturated: {out:?}");
    let got = out.achieved_forces()[0];
    assert!((got[0] - force[0]).hypot(got[1] - force[1]) <= 1e-9 * most, "{got:?} vs {force:?}");
}

#[test]
fn a_request_beyond_reach_is_saturated_and_a_zero_request_is_not() {
    let bounds = [0.9; 4];
    let out = solve(&CORNERS, &bounds, 0, [0.5, 0.0], [0.5, 0.0]);
    assert!(out.saturated && out.at_bound >= 1, "{out:?}");
    assert!(out.residual > 0.1, "most of 0.5 N is missing: {}", out.residual);
    for cycle_slots in [0, 8] {
        let out = solve(&CORNERS, &bounds, cycle_slots, [0.5, 0.0], [0.0, 0.0]);
        assert!(!out.saturated && out.at_bound == 0 && out.residual == 0.0, "{out:?}");
        assert!(out.k().iter().all(|&k| k == 0.0));
    }
}

#[test]
fn the_reach_along_any_direction_is_met_and_five_percent_more_is_saturated() {
    let centers = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5], [0.2, 0.7], [-0.4, -0.8]];
    let bounds = [0.9, 0.6, 0.75, 0.9, 0.4, 0.8];
    for (i, p) in [[0.5, 0.0], [-0.75, 0.25], [0.1, -0.3], [0.9, 0.45]].into_iter().enumerate() {
        for a in 0..12 {
            let angle = (a as f64 + 0.37 * i as f64) * core::f64::consts::TAU / 12.0;
            let d = [angle.cos(), angle.sin()];
            let reach = max_force_in(&centers, &bounds, MU_M_G, 0, 0.0, p, d);
            let f = scaled(d, reach);
            let out = solve(&centers, &bounds, 0, p, f);
            assert!(met(&out, f) && !out.saturated, "{p:?} {d:?}: {reach} N not met: {out:?}");
            let more = scaled(d, 1.05 * reach);
            let out = solve(&centers, &bounds, 0, p, more);
            assert!(out.saturated && !met(&out, more), "{p:?} {d:?}: 1.05 × {reach} N met: {out:?}");
        }
    }
}

#[test]
fn sparse_cycles_reach_the_strongest_center_alone() {
    let bounds = [0.9, 0.6, 0.75, 0.9];
    let p = [0.3, 0.1];
    let (most, d) = max_force_at(&CORNERS, &bounds, MU_M_G, 8, 0.1, p);
    assert!((most - MU_M_G * 0.9).abs() < 1e-15, "{most}");
    let out = solve(&CORNERS, &bounds, 8, p, scaled(d, most));
    assert!(met(&out, scaled(d, most)) && !out.saturated && out.at_bound >= 1, "{out:?}");
    let out = solve(&CORNERS, &bounds, 8, p, scaled(d, 1.05 * most));
    assert!(out.saturated, "{out:?}");
}
