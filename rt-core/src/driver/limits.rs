//! Actuator limits at the driver boundary and the one clamp policy.

use super::{ActuatorCommand, MAX_ACTUATORS, WriteError};
use crate::motion::Rig;

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
#[inline]
pub fn apply_limits(
    limits: &ActuatorLimits,
    cmd: &ActuatorCommand,
    out: &mut ActuatorCommand,
) -> Result<u32, WriteError> {
    let n = limits.count.min(MAX_ACTUATORS);
    // Branch-free scan first (the common case); the index only on failure.
    let finite =
        |i: usize| cmd.position[i].is_finite() & cmd.velocity[i].is_finite() & cmd.force[i].is_finite();
    if !(0..n).fold(true, |ok, i| ok & finite(i)) {
        let actuator = (0..n).find(|&i| !finite(i)).unwrap_or(0);
        return Err(WriteError::NonFinite { actuator });
    }
    let mut clamped = 0;
    // Limits are validated positive and v is finite: two compares (what
    // minsd/maxsd do), not f64::clamp, which re-checks its bounds per call.
    let mut clamp = |v: f64, lim: f64| {
        let c = if v > lim { lim } else { v };
        let c = if c < -lim { -lim } else { c };
        clamped += (c != v) as u32;
        c
    };
    for i in 0..n {
        out.position[i] = clamp(cmd.position[i], limits.stroke[i]);
        out.velocity[i] = clamp(cmd.velocity[i], limits.velocity[i]);
        out.force[i] = clamp(cmd.force[i], limits.force[i]);
    }
    for i in n..MAX_ACTUATORS {
        out.position[i] = 0.0;
        out.velocity[i] = 0.0;
        out.force[i] = 0.0;
    }
    Ok(clamped)
}
