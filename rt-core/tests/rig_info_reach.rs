//! `RigInfo.max_part_force_n`, what the core tells clients on
//! `upm/rig_info`, against what its solver does: a request of that force
//! at `max_part_force_at` in the best direction is met, 5 % more is
//! saturated, on the paper's cycle and on sparse cycles.

use rt_core::{CoreParams, rig_info};
use upm_solver::{ForceConstraint, PartShape, Problem, Solution, Solver, SolverCapacity, SolverParams};
use upm_solver::{SATURATION_TOLERANCE, max_force_at};

fn met(out: &Solution, force: [f64; 2]) -> bool {
    out.residual <= SATURATION_TOLERANCE * force[0].hypot(force[1])
}

#[test]
fn the_rigs_max_part_force_is_met_in_its_best_direction_and_five_percent_more_is_not() {
    for cycle_slots in [0, 12] {
        let mut params = CoreParams::default();
        params.motion.cycle_slots = cycle_slots;
        let bounds = params.playable_k_bounds().expect("playable");
        let info = rig_info(&params, &bounds, "upm_test_", 30.0);
        let (at, most) = (info.max_part_force_at, info.max_part_force_n);
        let [hx, hy] = params.motion.plate_half_extent;
        assert!(at[0].abs() <= hx && at[1].abs() <= hy, "{at:?} on the plate");
        let (here, d) = max_force_at(
            &params.plate.centers,
            &bounds,
            params.plate.mu_m_g,
            cycle_slots,
            info.keep_out_m,
            at,
        );
        assert_eq!(here, most);
        let mut s =
            Solver::new(SolverCapacity::DEFAULT, SolverParams { cycle_slots, ..SolverParams::default() });
        let k_max = bounds.iter().fold(0.0, |a: f64, &b| a.max(b));
        let mut out = s.new_solution();
        for (gain, want_met) in [(1.0, true), (1.05, false)] {
            let force = [d[0] * gain * most, d[1] * gain * most];
            let parts = [ForceConstraint { position: at, force: Some(force), shape: PartShape::Point }];
            let problem = Problem {
                mu_m_g: params.plate.mu_m_g,
                k_max,
                centers: &params.plate.centers,
                parts: &parts,
                curls: &[],
                k_bounds: &bounds,
            };
            s.forget_warm_start();
            s.solve(&problem, &mut out).expect("solves");
            assert_eq!(
                (met(&out, force), out.saturated),
                (want_met, !want_met),
                "cycle_slots {cycle_slots}, {gain} × {most} N at {at:?}: {out:?}"
            );
        }
    }
}
