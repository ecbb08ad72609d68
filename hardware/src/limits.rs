//! Actuator limits at the driver boundary and the one clamp policy.

use super::{ActuatorCommand, MAX_ACTUATORS, WriteError};
use upm_motion::Rig;

/// Limits per actuator (entries beyond `count` unused).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ActuatorLimits {
    pub count: usize,
    pub stroke: [f64; MAX_ACTUATORS],
    pub velocity: [f64; MAX_ACTUATORS],
    pub force: [f64; MAX_ACTUATORS],
}

impl ActuatorLimits {
    pub fn from_rig(rig: &Rig) -> Self {
        let p = rig.params();
        let mut l = Self { count: p.count, ..Self::default() };
        for (i, a) in p.actuators[..p.count].iter().enumerate() {
            l.stroke[i] = a.stroke;
            l.velocity[i] = a.max_velocity;
            l.force[i] = a.max_force;
        }
        l
    }
}

/// Copy `cmd` into `out` within `limits`: non-finite → Err (out untouched);
/// otherwise clamp and return how many entries were clamped. Entries beyond
/// `count` are zeroed.
#[inline(always)]
pub fn apply_limits(
    limits: &ActuatorLimits,
    cmd: &ActuatorCommand,
    out: &mut ActuatorCommand,
) -> Result<u32, WriteError> {
    let n = limits.count.min(MAX_ACTUATORS);
    // Every slot, branch-free, with entries beyond `count` masked off: the
    // fixed-width loops vectorise. `x − x == 0` is the finite test as one
    // float compare. The index is looked for only on failure.
    #[allow(clippy::eq_op)] // x − x is 0 for finite x, NaN otherwise: the point.
    let finite = |x: f64| x - x == 0.0;
    let entry_ok = |i: usize| finite(cmd.position[i]) & finite(cmd.velocity[i]) & finite(cmd.force[i]);
    let mut ok = true;
    for i in 0..MAX_ACTUATORS {
        ok &= entry_ok(i) | (i >= n);
    }
    if !ok {
        let actuator = (0..n).find(|&i| !entry_ok(i)).unwrap_or(0);
        return Err(WriteError::NonFinite { actuator });
    }
    let mut clamped = 0;
    for i in 0..MAX_ACTUATORS {
        let live = i < n;
        // Limits are validated positive and v is finite where live: two
        // compares (what minsd/maxsd do), not f64::clamp, which re-checks
        // its bounds per call.
        let mut clamp = |v: f64, lim: f64| {
            let c = if v > lim { lim } else { v };
            let c = if c < -lim { -lim } else { c };
            clamped += (live & (c != v)) as u32;
            if live { c } else { 0.0 }
        };
        out.position[i] = clamp(cmd.position[i], limits.stroke[i]);
        out.velocity[i] = clamp(cmd.velocity[i], limits.velocity[i]);
        out.force[i] = clamp(cmd.force[i], limits.force[i]);
    }
    Ok(clamped)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits() -> ActuatorLimits {
        let mut l = ActuatorLimits { count: 3, ..ActuatorLimits::default() };
        for i in 0..3 {
            (l.stroke[i], l.velocity[i], l.force[i]) = (1.0, 2.0, 3.0);
        }
        l
    }

    /// Live entries are clamped and counted; entries beyond `count` are
    /// zeroed whatever they hold, and never counted or refused.
    #[test]
    fn clamps_live_entries_and_zeroes_the_rest() {
        let mut cmd = ActuatorCommand::HOME;
        cmd.position[..3].copy_from_slice(&[0.5, -1.5, 1.0]);
        cmd.velocity[..3].copy_from_slice(&[2.5, 0.0, -2.0]);
        cmd.force[..3].copy_from_slice(&[-9.0, 3.0, 0.1]);
        cmd.position[3] = f64::NAN;
        cmd.force[7] = 1e9;
        let mut out = ActuatorCommand::default();
        assert_eq!(apply_limits(&limits(), &cmd, &mut out), Ok(3));
        assert_eq!(out.position[..3], [0.5, -1.0, 1.0]);
        assert_eq!(out.velocity[..3], [2.0, 0.0, -2.0]);
        assert_eq!(out.force[..3], [-3.0, 3.0, 0.1]);
        assert!(out.position[3..].iter().chain(&out.velocity[3..]).chain(&out.force[3..]).all(|&v| v == 0.0));
    }

    #[test]
    fn non_finite_live_entry_is_refused_with_its_index() {
        let mut cmd = ActuatorCommand::HOME;
        cmd.velocity[2] = f64::INFINITY;
        let mut out = ActuatorCommand::default();
        assert_eq!(apply_limits(&limits(), &cmd, &mut out), Err(WriteError::NonFinite { actuator: 2 }));
        assert_eq!(out, ActuatorCommand::default());
    }
}
