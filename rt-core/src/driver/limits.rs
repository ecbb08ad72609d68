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
    for i in 0..n {
        if !(cmd.position[i].is_finite() && cmd.velocity[i].is_finite() && cmd.force[i].is_finite()) {
            return Err(WriteError::NonFinite { actuator: i });
        }
    }
    let mut clamped = 0;
    let mut clamp = |v: f64, lim: f64| {
        if v.abs() > lim {
            clamped += 1;
            v.clamp(-lim, lim)
        } else {
            v
        }
    };
    for i in 0..MAX_ACTUATORS {
        if i < n {
            out.position[i] = clamp(cmd.position[i], limits.stroke[i]);
            out.velocity[i] = clamp(cmd.velocity[i], limits.velocity[i]);
            out.force[i] = clamp(cmd.force[i], limits.force[i]);
        } else {
            out.position[i] = 0.0;
            out.velocity[i] = 0.0;
            out.force[i] = 0.0;
        }
    }
    Ok(clamped)
}
