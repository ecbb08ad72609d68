//! What the core publishes once on `upm/rig_info`: the values it really
//! runs with, read from the same functions the solve stage uses, so the
//! description cannot drift from the rig (start-up only; it allocates).

use ipc_types::{RigCenter, RigInfo, ValidationLimits};

use super::params::CoreParams;
use upm_solver::{SATURATION_FLOOR, SATURATION_TOLERANCE, SolverParams, max_force_on_plate};

/// The solver parameters the solve stage runs with.
pub(crate) fn stage_solver_params(params: &CoreParams) -> SolverParams {
    SolverParams { cycle_slots: params.motion.cycle_slots, ..SolverParams::default() }
}

/// The limits the solve stage validates messages against (`now_ns` and
/// `max_age_ns` are set per message).
pub(crate) fn stage_limits(params: &CoreParams, k_max: f64) -> ValidationLimits {
    let mut limits = ValidationLimits::new(params.motion.plate_half_extent, 0);
    limits.max_future_skew_ns = params.safety.max_future_skew_ns;
    limits.center_count = params.plate.centers.len() as u32;
    limits.k_max = k_max;
    limits
}

/// The rig as the core runs it: `k_bounds` are the per-center bounds the
/// solve stage solves under, `vision_frame_hz` the configured rate of
/// PartStates (0: not known).
pub fn rig_info(params: &CoreParams, k_bounds: &[f64], prefix: &str, vision_frame_hz: f64) -> RigInfo {
    let k_top = k_bounds.iter().fold(0.0, |a: f64, &k| a.max(k));
    let limits = stage_limits(params, k_top);
    let solver = stage_solver_params(params);
    let mut m = RigInfo::new();
    for (&[x, y], &k_bound) in params.plate.centers.iter().zip(k_bounds) {
        // CoreParams::validate caps the centers at MAX_CENTERS.
        let _ = m.push(RigCenter { x, y, k_bound });
    }
    let ms = |ns: u64| ns as f64 / 1e6;
    let slots = params.longest_cycle();
    let best = max_force_on_plate(
        &params.plate.centers,
        k_bounds,
        params.plate.mu_m_g,
        params.motion.cycle_slots,
        solver.sparse_keep_out,
        params.motion.plate_half_extent,
    );
    m.seq = 1;
    m.stamp_ns = ipc_types::monotonic_now_ns();
    m.core_pid = std::process::id();
    m.cycle_slots = params.motion.cycle_slots as u32;
    m.class_count = limits.part_class_count;
    m.friction_class_count = limits.friction_class_count;
    m.slot_ticks = params.motion.slot_ticks;
    let cycle_ticks = slots as u64 * u64::from(params.motion.slot_ticks);
    m.cycle_period_ns = (cycle_ticks as f64 * 1e9 / params.motion.tick_hz).round() as u64;
    m.tick_hz = params.motion.tick_hz;
    m.vision_frame_hz =
        if vision_frame_hz.is_finite() && vision_frame_hz > 0.0 { vision_frame_hz } else { 0.0 };
    m.mu_m_g = params.plate.mu_m_g;
    m.plate_half_extent = params.motion.plate_half_extent;
    m.k_max = params.motion.k_max;
    m.max_part_force_n = best.force;
    m.max_part_force_at = best.at;
    m.keep_out_m = solver.sparse_keep_out;
    m.saturation_tolerance = SATURATION_TOLERANCE;
    m.saturation_floor = SATURATION_FLOOR;
    m.parts_max_age_ms = ms(params.safety.parts_max_age_ns);
    m.request_max_age_ms = ms(params.safety.request_max_age_ns);
    m.max_future_skew_ms = ms(limits.max_future_skew_ns);
    m.set_prefix(prefix);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_rig_describes_itself_validly() {
        let params = CoreParams::default();
        let bounds = params.playable_k_bounds().expect("playable");
        let m = rig_info(&params, &bounds, "upm_", 30.0);
        let limits = ValidationLimits::new([1.0, 1.0], m.stamp_ns);
        assert_eq!(m.validate(&limits), Ok(()));
        assert_eq!(m.len(), 4);
        assert_eq!(m.cycle_period_ns, 4 * 40 * 100_000);
        assert_eq!(m.prefix_str(), "upm_");
        assert!(m.centers().iter().zip(&bounds).all(|(c, &u)| c.k_bound == u));
    }
}
