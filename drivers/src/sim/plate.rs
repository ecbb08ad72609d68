//! The plate and its actuator model.

use rt_core::driver::{ActuatorCommand, MAX_ACTUATORS};
use rt_core::motion::{Pose, Rig, Twist};

use super::config::ActuatorModel;
use crate::rng::SplitMix64;

/// Rigid plate state; `acc` is held constant over the current substep.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Plate {
    pub pose: Pose,
    pub vel: Twist,
    pub acc: Twist,
    /// Actuator forces applied over the current substep (N).
    pub force: [f64; MAX_ACTUATORS],
    /// Substeps in which at least one actuator force hit its limit.
    pub saturated: u64,
}

/// Target of the current tick, derived once per accepted command. A command
/// is the setpoint for the end of the tick; the servo's reference moves
/// linearly from the previous setpoint to it during the tick.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Target {
    pub pose: Pose,
    pub vel: Twist,
    pub prev_pose: Pose,
    pub prev_vel: Twist,
    pub ff: [f64; MAX_ACTUATORS],
}

impl Target {
    pub fn from_command(rig: &Rig, cmd: &ActuatorCommand, previous: &Target) -> Self {
        let pose = rig.pose_from_actuators(&cmd.position);
        let vel = rig.twist_from_actuators(&pose, &cmd.velocity);
        Self { pose, vel, prev_pose: previous.pose, prev_vel: previous.vel, ff: cmd.force }
    }

    /// Reference pose and velocity at fraction `f` of the tick.
    #[inline]
    fn reference(&self, f: f64) -> ([f64; 3], [f64; 3]) {
        let l = |a: f64, b: f64| a + (b - a) * f;
        let (p, q, v, w) = (&self.prev_pose, &self.pose, &self.prev_vel, &self.vel);
        ([l(p.x, q.x), l(p.y, q.y), l(p.theta, q.theta)], [l(v.x, w.x), l(v.y, w.y), l(v.theta, w.theta)])
    }
}

impl Plate {
    /// Set `acc` for a substep of length `s`; `remaining` substeps in this
    /// tick including this one (the ideal model lands on the target at the
    /// end of the tick).
    #[inline]
    pub fn plan_substep(
        &mut self,
        model: ActuatorModel,
        rig: &Rig,
        target: &Target,
        s: f64,
        remaining: u32,
        fraction: f64,
        noise: f64,
        rng: &mut SplitMix64,
    ) {
        match model {
            ActuatorModel::Ideal => {
                let t = s * remaining as f64;
                self.acc = Twist {
                    x: (target.vel.x - self.vel.x) / t,
                    y: (target.vel.y - self.vel.y) / t,
                    theta: (target.vel.theta - self.vel.theta) / t,
                };
                self.force = target.ff;
            }
            ActuatorModel::SecondOrder { bandwidth_hz, damping } => {
                let w = core::f64::consts::TAU * bandwidth_hz;
                let (kp, kd) = (w * w, 2.0 * damping * w);
                let p = rig.params();
                let (rp, rv) = target.reference(fraction);
                let e = [rp[0] - self.pose.x, rp[1] - self.pose.y, rp[2] - self.pose.theta];
                let ed = [rv[0] - self.vel.x, rv[1] - self.vel.y, rv[2] - self.vel.theta];
                let inertia = [p.plate_mass, p.plate_mass, p.plate_inertia];
                let pd = Twist {
                    x: kp * e[0] + kd * ed[0],
                    y: kp * e[1] + kd * ed[1],
                    theta: kp * e[2] + kd * ed[2],
                };
                let mut f = [0.0; MAX_ACTUATORS];
                rig.feedforward_forces(&pd, &mut f);
                let mut sat = false;
                for (i, fi) in f.iter_mut().enumerate().take(p.count) {
                    let lim = p.actuators[i].max_force;
                    let mut v = *fi + target.ff[i];
                    if noise > 0.0 {
                        v += noise * rng.normal();
                    }
                    if v.abs() > lim {
                        sat = true;
                        v = v.clamp(-lim, lim);
                    }
                    *fi = v;
                }
                self.saturated += sat as u64;
                let q = rig.generalized_force(&self.pose, &f);
                self.acc = Twist { x: q[0] / inertia[0], y: q[1] / inertia[1], theta: q[2] / inertia[2] };
                self.force = f;
            }
        }
    }

    /// Integrate pose and velocity over `s` with the planned acceleration.
    #[inline]
    pub fn integrate(&mut self, s: f64) {
        let a = self.acc;
        self.pose.x += self.vel.x * s + 0.5 * a.x * s * s;
        self.pose.y += self.vel.y * s + 0.5 * a.y * s * s;
        self.pose.theta += self.vel.theta * s + 0.5 * a.theta * s * s;
        self.vel.x += a.x * s;
        self.vel.y += a.y * s;
        self.vel.theta += a.theta * s;
    }
}
