//! What a slipping part really feels over one cycle. The paper's model
//! takes the part at rest: each slot pushes μmg·k along its tangent. But a
//! part pushed by one slot keeps that velocity into the next, whose plate
//! velocity points elsewhere, so the friction it feels there is turned;
//! with a min-norm answer's large opposing k this loses a fixed fraction
//! of the request whatever its size (BENCHMARKS.md, issue 25). This
//! integrates a point mass under Coulomb friction on the plate's motion
//! (as [`PlateFollow`] has it follow the command), from the part's
//! velocity at the cycle's start, and returns its average acceleration
//! over the cycle; [`cycle_mean_twist`] does the same
//! for a rigid patch, spin included.
//!
//! The part moves and turns as it is pushed, and the plate is read where
//! it is. Cost: `SUBSTEPS` × cycle ticks evaluations of the motion (times
//! the patch's points), no allocation. Limits: kinetic friction only (a
//! part that matches the plate's velocity chatters about it rather than
//! sticking; the slots are hard enough that parts slide), and the plate
//! follows its command as [`PlateFollow`] says (exactly, or through a
//! servo model of the drives in small angles).

use super::PlateMotion;
use super::plate_follow::{PlateFollow, PlatePath};
use crate::solver::{PartShape, PatchPoints};

/// Integration steps per motor tick: the fast phase lasts a few ticks.
/// Against a finely stepped ideal plate, the cycle's mean force is off by
/// 1.8 % (median of `upm bench fidelity`'s parts) at 4 and 0.13 % at 32.
const SUBSTEPS: u64 = 32;

/// The mean acceleration over one cycle of `motion` of a point mass at
/// `position` (world, m) moving at `velocity` (m/s) at the cycle's start,
/// under kinetic friction `mu_g` (m/s²) only. Zero for an empty motion.
pub fn cycle_mean_acceleration(
    motion: &PlateMotion,
    position: [f64; 2],
    velocity: [f64; 2],
    mu_g: f64,
) -> [f64; 2] {
    let point = PartShape::Point.patch_points();
    cycle_mean_twist(motion, PlateFollow::Exact, position, &point, velocity, 0.0, mu_g).0
}

/// As [`cycle_mean_acceleration`] for a rigid part pressing at `patch`'s
/// points, on a plate that follows `motion` as `follow` says: its velocity
/// and spin through the cycle. Returns the mean
/// acceleration of the centroid (at `position`, world) and the mean angular
/// acceleration. A point (ρ² = 0) does not spin.
pub fn cycle_mean_twist(
    motion: &PlateMotion,
    follow: PlateFollow,
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
    // The part's travel and turn so far: the plate under it is read where it is now.
    let (mut at, mut turn) = (position, 0.0f64);
    let points = &patch.points[..patch.count];
    let mut plate_path = PlatePath::new(motion, follow, SUBSTEPS);
    for _ in 0..ticks {
        let (pose, twist) = plate_path.next();
        let (sin, cos) = turn.sin_cos();
        let (mut f, mut tau) = ([0.0; 2], 0.0);
        for &(q0, weight) in points {
            let q = [cos * q0[0] - sin * q0[1], sin * q0[0] + cos * q0[1]];
            let plate = twist.at(&pose, [at[0] + q[0], at[1] + q[1]]);
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
        let v0 = v;
        v[0] += mu_g * f[0] * h;
        v[1] += mu_g * f[1] * h;
        at[0] += 0.5 * (v0[0] + v[0]) * h;
        at[1] += 0.5 * (v0[1] + v[1]) * h;
        let w0 = w;
        if patch.rho2 > 0.0 {
            w += mu_g * tau / patch.rho2 * h;
        }
        turn += 0.5 * (w0 + w) * h;
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
        let (a, alpha) = cycle_mean_twist(&m, PlateFollow::Exact, [0.3, 0.0], &point, [0.0; 2], 0.0, MU_G);
        assert_eq!(a, cycle_mean_acceleration(&m, [0.3, 0.0], [0.0; 2], MU_G));
        assert_eq!(alpha, 0.0);
        // A disc near the center: the slot's curl turns it the slot's way
        // (k > 0: counter-clockwise).
        let disc = crate::solver::PartShape::Disc { radius: 0.05 }.patch_points();
        let (_, alpha) = cycle_mean_twist(&m, PlateFollow::Exact, [-0.1, 0.0], &disc, [0.0; 2], 0.0, MU_G);
        assert!(alpha > 0.0, "{alpha}");
    }

    #[test]
    fn an_empty_motion_pushes_nothing() {
        let m = PlateMotion::new(MotionParams::default()).expect("motion");
        assert_eq!(cycle_mean_acceleration(&m, [0.3, 0.0], [0.01, 0.0], MU_G), [0.0; 2]);
    }
}
