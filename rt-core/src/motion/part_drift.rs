//! What a slipping part really feels over one cycle. The paper's model
//! takes the part at rest: each slot pushes μmg·k along its tangent. But a
//! part pushed by one slot keeps that velocity into the next, whose plate
//! velocity points elsewhere, so the friction it feels there is turned;
//! with a min-norm answer's large opposing k this loses a fixed fraction
//! of the request whatever its size (BENCHMARKS.md, issue 25). This
//! integrates a point mass under Coulomb friction on the commanded plate
//! motion, from the part's velocity at the cycle's start, and returns its
//! average acceleration over the cycle; [`cycle_mean_twist`] does the same
//! for a rigid patch, spin included.
//!
//! Cost: `SUBSTEPS` × cycle ticks evaluations of the motion (times the
//! patch's points), no allocation. Limits: the part is taken to slip
//! throughout (no sticking), it does not move far enough within a cycle
//! for its position to matter, and the plate follows its command exactly.

use super::PlateMotion;
use crate::solver::PatchPoints;

/// Integration steps per motor tick.
const SUBSTEPS: u64 = 4;

/// The mean acceleration over one cycle of `motion` of a point mass at
/// `position` (world, m) moving at `velocity` (m/s) at the cycle's start,
/// under kinetic friction `mu_g` (m/s²) only. Zero for an empty motion.
pub fn cycle_mean_acceleration(
    motion: &PlateMotion,
    position: [f64; 2],
    velocity: [f64; 2],
    mu_g: f64,
) -> [f64; 2] {
    let ticks = motion.cycle_ticks() * SUBSTEPS;
    let duration = motion.cycle_duration();
    if ticks == 0 || !(duration > 0.0) {
        return [0.0; 2];
    }
    let h = duration / ticks as f64;
    let mut v = velocity;
    for i in 0..ticks {
        let s = motion.sample((i as f64 + 0.5) * h);
        let plate = s.velocity.at(&s.pose, position);
        let (rx, ry) = (plate[0] - v[0], plate[1] - v[1]);
        let r = (rx * rx + ry * ry).sqrt();
        if r > 0.0 {
            v[0] += mu_g * rx / r * h;
            v[1] += mu_g * ry / r * h;
        }
    }
    [(v[0] - velocity[0]) / duration, (v[1] - velocity[1]) / duration]
}

/// As [`cycle_mean_acceleration`] for a rigid part pressing at `patch`'s
/// points: its velocity and spin through the cycle. Returns the mean
/// acceleration of the centroid (at `position`, world) and the mean angular
/// acceleration. A point (ρ² = 0) does not spin.
pub fn cycle_mean_twist(
    motion: &PlateMotion,
    position: [f64; 2],
    patch: &PatchPoints,
    velocity: [f64; 2],
    spin: f64,
    mu_g: f64,
) -> ([f64; 2], f64) {
    let ticks = motion.cycle_ticks() * SUBSTEPS;
    let duration = motion.cycle_duration();
    if ticks == 0 || !(duration > 0.0) {
        return ([0.0; 2], 0.0);
    }
    let h = duration / ticks as f64;
    let (mut v, mut w) = (velocity, spin);
    let points = &patch.points[..patch.count];
    for i in 0..ticks {
        let s = motion.sample((i as f64 + 0.5) * h);
        let (mut f, mut tau) = ([0.0; 2], 0.0);
        for &(q, weight) in points {
            let plate = s.velocity.at(&s.pose, [position[0] + q[0], position[1] + q[1]]);
            // Plate minus part at the contact: v + ω × q for the part.
            let (rx, ry) = (plate[0] - (v[0] - w * q[1]), plate[1] - (v[1] + w * q[0]));
            let r = (rx * rx + ry * ry).sqrt();
            if r > 0.0 {
                let (ux, uy) = (weight * rx / r, weight * ry / r);
                f[0] += ux;
                f[1] += uy;
                tau += q[0] * uy - q[1] * ux;
            }
        }
        v[0] += mu_g * f[0] * h;
        v[1] += mu_g * f[1] * h;
        if patch.rho2 > 0.0 {
            w += mu_g * tau / patch.rho2 * h;
        }
    }
    ([(v[0] - velocity[0]) / duration, (v[1] - velocity[1]) / duration], (w - spin) / duration)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::{MotionParams, ScheduleEntry};

    const MU_G: f64 = 0.25 * 9.81;

    fn motion(entries: &[ScheduleEntry]) -> PlateMotion {
        let mut m = PlateMotion::new(MotionParams::default()).expect("motion");
        m.set_schedule(entries).expect("playable");
        m
    }

    #[test]
    fn one_slot_on_a_part_at_rest_gives_the_papers_force() {
        // A part 0.5 m from the center: the tangent is +y, the force μg·k.
        let m = motion(&[ScheduleEntry { center: [-0.2, 0.0], k: 0.4 }]);
        let a = cycle_mean_acceleration(&m, [0.3, 0.0], [0.0; 2], MU_G);
        assert!(a[0].abs() < 1e-3 * MU_G, "{a:?}");
        assert!((a[1] - 0.4 * MU_G).abs() < 0.02 * 0.4 * MU_G, "{a:?}");
    }

    #[test]
    fn velocity_across_the_plates_is_dragged_out() {
        // Moving along x at the start, where the slot's plate velocity is
        // along y: friction takes some of the x velocity back.
        let m = motion(&[ScheduleEntry { center: [-0.2, 0.0], k: 0.0 }]);
        let a = cycle_mean_acceleration(&m, [0.3, 0.0], [0.01, 0.0], MU_G);
        assert!(a[0] < -0.01 * MU_G, "{a:?}");
    }

    #[test]
    fn a_point_patch_moves_as_the_point_model_and_a_disc_spins_up() {
        let m = motion(&[ScheduleEntry { center: [-0.2, 0.0], k: 0.4 }]);
        let point = crate::solver::PartShape::Point.patch_points();
        let (a, alpha) = cycle_mean_twist(&m, [0.3, 0.0], &point, [0.0; 2], 0.0, MU_G);
        assert_eq!(a, cycle_mean_acceleration(&m, [0.3, 0.0], [0.0; 2], MU_G));
        assert_eq!(alpha, 0.0);
        // A disc near the center: the slot's curl turns it the slot's way
        // (k > 0: counter-clockwise).
        let disc = crate::solver::PartShape::Disc { radius: 0.05 }.patch_points();
        let (_, alpha) = cycle_mean_twist(&m, [-0.1, 0.0], &disc, [0.0; 2], 0.0, MU_G);
        assert!(alpha > 0.0, "{alpha}");
    }

    #[test]
    fn an_empty_motion_pushes_nothing() {
        let m = PlateMotion::new(MotionParams::default()).expect("motion");
        assert_eq!(cycle_mean_acceleration(&m, [0.3, 0.0], [0.01, 0.0], MU_G), [0.0; 2]);
    }
}
