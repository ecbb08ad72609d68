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
//! it is. Cost: [`DriftParams::substeps`] × cycle ticks evaluations of the
//! motion (times the patch's points), no allocation. Limits: kinetic friction only (a
//! part that matches the plate's velocity chatters about it rather than
//! sticking; the slots are hard enough that parts slide), and the plate
//! follows its command as [`PlateFollow`] says (exactly, or through a
//! servo model of the drives in small angles).

use core::fmt;

use super::plate_follow::PlateFollow;
use super::plate_path::PlatePath;
use super::{PlateMotion, Pose, Twist};
use upm_solver::{PartShape, PatchPoints};

/// How a part's cycle is integrated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriftParams {
    /// How the plate follows its command.
    pub follow: PlateFollow,
    /// Integration steps per motor tick: the fast phase lasts a few ticks.
    /// Against a finely stepped ideal plate, the cycle's mean force is off
    /// by 1.8 % (median of `upm bench fidelity`'s parts) at 4 and 0.13 % at
    /// 32 (the default).
    pub substeps: u64,
}

impl Default for DriftParams {
    fn default() -> Self {
        Self { follow: PlateFollow::Exact, substeps: 32 }
    }
}

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
    cycle_mean_twist(motion, DriftParams::default(), position, &point, velocity, 0.0, mu_g).0
}

/// As [`cycle_mean_acceleration`] for a rigid part pressing at `patch`'s
/// points, on a plate that follows `motion` as `params` says: its velocity
/// and spin through the cycle. Returns the mean
/// acceleration of the centroid (at `position`, world) and the mean angular
/// acceleration. A point (ρ² = 0) does not spin.
pub fn cycle_mean_twist(
    motion: &PlateMotion,
    params: DriftParams,
    position: [f64; 2],
    patch: &PatchPoints,
    velocity: [f64; 2],
    spin: f64,
    mu_g: f64,
) -> ([f64; 2], f64) {
    let substeps = params.substeps.max(1);
    let pieces = motion.cycle_ticks() * substeps;
    let mut path = PlatePath::new(motion, params.follow, substeps);
    let plate = (0..pieces).map(|_| path.next());
    integrate(plate, pieces, motion.cycle_duration(), position, patch, velocity, spin, mu_g)
}

/// The plate through one cycle, sampled once so that many parts can be
/// integrated on it ([`PlateTrace::mean_twist`]) at a few ns per piece
/// instead of a motion sample each. Its buffer is allocated once
/// ([`PlateTrace::with_capacity`]); recording allocates nothing.
#[derive(Debug, Clone)]
pub struct PlateTrace {
    pieces: Vec<(Pose, Twist)>,
    duration: f64,
}

/// [`PlateTrace::record`]: the cycle has more pieces than the trace holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TraceTooLong {
    pub pieces: u64,
    pub capacity: usize,
}

impl fmt::Display for TraceTooLong {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a cycle of {} pieces, the plate trace holds {}", self.pieces, self.capacity)
    }
}

impl core::error::Error for TraceTooLong {}

impl PlateTrace {
    /// Room for `pieces` (cycle ticks × substeps); an empty trace.
    pub fn with_capacity(pieces: usize) -> Self {
        Self { pieces: Vec::with_capacity(pieces), duration: 0.0 }
    }

    /// Sample one cycle of `motion` as `params` says, replacing what the
    /// trace held. On error the trace is empty.
    pub fn record(&mut self, motion: &PlateMotion, params: DriftParams) -> Result<(), TraceTooLong> {
        self.pieces.clear();
        self.duration = 0.0;
        let substeps = params.substeps.max(1);
        let pieces = motion.cycle_ticks().saturating_mul(substeps);
        if pieces > self.pieces.capacity() as u64 {
            return Err(TraceTooLong { pieces, capacity: self.pieces.capacity() });
        }
        let mut path = PlatePath::new(motion, params.follow, substeps);
        // Within capacity (checked above): no allocation.
        self.pieces.extend((0..pieces).map(|_| path.next()));
        self.duration = motion.cycle_duration();
        Ok(())
    }

    /// [`cycle_mean_twist`] on the recorded cycle; bit for bit the same
    /// figures as on the motion it recorded.
    pub fn mean_twist(
        &self,
        position: [f64; 2],
        patch: &PatchPoints,
        velocity: [f64; 2],
        spin: f64,
        mu_g: f64,
    ) -> ([f64; 2], f64) {
        let n = self.pieces.len() as u64;
        integrate(self.pieces.iter().copied(), n, self.duration, position, patch, velocity, spin, mu_g)
    }
}

/// The part through `pieces` equal pieces of a cycle of `duration` (s),
/// the plate's pose and twist at each piece's middle given by `plate`.
#[allow(clippy::too_many_arguments)]
fn integrate(
    plate: impl Iterator<Item = (Pose, Twist)>,
    pieces: u64,
    duration: f64,
    position: [f64; 2],
    patch: &PatchPoints,
    velocity: [f64; 2],
    spin: f64,
    mu_g: f64,
) -> ([f64; 2], f64) {
    if pieces == 0 || !(duration > 0.0) {
        return ([0.0; 2], 0.0);
    }
    let h = duration / pieces as f64;
    let (mut v, mut w) = (velocity, spin);
    // The part's travel and turn so far: the plate under it is read where it is now.
    let (mut at, mut turn) = (position, 0.0f64);
    let points = &patch.points[..patch.count];
    for (pose, twist) in plate {
        // A point's one contact sits at its centroid: no turn to apply.
        let (sin, cos) = if patch.rho2 > 0.0 { turn.sin_cos() } else { (0.0, 1.0) };
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
    use crate::{MotionParams, ScheduleEntry};

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
        let point = upm_solver::PartShape::Point.patch_points();
        let (a, alpha) =
            cycle_mean_twist(&m, DriftParams::default(), [0.3, 0.0], &point, [0.0; 2], 0.0, MU_G);
        assert_eq!(a, cycle_mean_acceleration(&m, [0.3, 0.0], [0.0; 2], MU_G));
        assert_eq!(alpha, 0.0);
        // A disc near the center: the slot's curl turns it the slot's way
        // (k > 0: counter-clockwise).
        let disc = upm_solver::PartShape::Disc { radius: 0.05 }.patch_points();
        let (_, alpha) =
            cycle_mean_twist(&m, DriftParams::default(), [-0.1, 0.0], &disc, [0.0; 2], 0.0, MU_G);
        assert!(alpha > 0.0, "{alpha}");
    }

    #[test]
    fn a_trace_integrates_as_the_motion_and_refuses_a_cycle_beyond_it() {
        let m = motion(&[
            ScheduleEntry { center: [-0.2, 0.0], k: 0.4 },
            ScheduleEntry { center: [0.5, 0.3], k: -0.3 },
        ]);
        let params = DriftParams { substeps: 4, ..DriftParams::default() };
        let pieces = (m.cycle_ticks() * 4) as usize;
        let mut trace = PlateTrace::with_capacity(pieces);
        trace.record(&m, params).expect("fits");
        let disc = upm_solver::PartShape::Disc { radius: 0.03 }.patch_points();
        let direct = cycle_mean_twist(&m, params, [0.1, 0.2], &disc, [0.01, -0.02], 0.3, MU_G);
        assert_eq!(trace.mean_twist([0.1, 0.2], &disc, [0.01, -0.02], 0.3, MU_G), direct);
        let mut short = PlateTrace::with_capacity(pieces - 1);
        assert_eq!(
            short.record(&m, params),
            Err(TraceTooLong { pieces: pieces as u64, capacity: pieces - 1 })
        );
        assert_eq!(short.mean_twist([0.1, 0.2], &disc, [0.0; 2], 0.0, MU_G), ([0.0; 2], 0.0));
    }

    #[test]
    fn an_empty_motion_pushes_nothing() {
        let m = PlateMotion::new(MotionParams::default()).expect("motion");
        assert_eq!(cycle_mean_acceleration(&m, [0.3, 0.0], [0.01, 0.0], MU_G), [0.0; 2]);
    }
}
