//! The plate and its actuator model.

use upm_hardware::{ActuatorCommand, MAX_ACTUATORS};
use upm_motion::{Pose, Rig, Twist, sin_cos};

use super::config::ActuatorModel;
use crate::rng::SplitMix64;

/// Rigid plate state; `acc` is held constant over the current substep.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Plate {
    pub pose: Pose,
    /// (sin θ, cos θ) of `pose`, kept in step with it by [`Plate::set_pose`].
    pub sc: (f64, f64),
    pub vel: Twist,
    pub acc: Twist,
    /// Actuator forces applied over the current substep (N).
    pub force: [f64; MAX_ACTUATORS],
    /// Their mean over the last whole tick (N): what a drive reports.
    pub tick_force: [f64; MAX_ACTUATORS],
    /// Substeps in which at least one actuator force hit its limit.
    pub saturated: u64,
}

impl Default for Plate {
    fn default() -> Self {
        Self {
            pose: Pose::HOME,
            sc: (0.0, 1.0),
            vel: Twist::default(),
            acc: Twist::default(),
            force: [0.0; MAX_ACTUATORS],
            tick_force: [0.0; MAX_ACTUATORS],
            saturated: 0,
        }
    }
}

/// Target of the current tick, derived once per accepted command. A command
/// is the setpoint for the end of the tick; the servo's reference moves
/// linearly from the previous setpoint to it during the tick, in actuator
/// space (the servo is closed on the actuator positions, as on a rig).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Target {
    /// Plate pose and twist of the command: solved only for the ideal model,
    /// which lands on them exactly.
    pub pose: Pose,
    pub vel: Twist,
    /// The command's positions and velocities projected to plate DoF
    /// ([`Rig::project`]), and those of the previous command.
    pub dof: [f64; 3],
    pub dof_vel: [f64; 3],
    pub prev_dof: [f64; 3],
    pub prev_dof_vel: [f64; 3],
    pub ff: [f64; MAX_ACTUATORS],
}

impl Target {
    /// Take an accepted command as the setpoint for the end of this tick
    /// (in place: the writer's hot path copies nothing else).
    #[inline(always)]
    pub fn accept(&mut self, model: ActuatorModel, rig: &Rig, cmd: &ActuatorCommand) {
        if let ActuatorModel::Ideal = model {
            self.pose = rig.pose_from_actuators(&cmd.position);
            self.vel = rig.twist_from_actuators(&self.pose, &cmd.velocity);
        }
        self.dof = rig.project(&cmd.position);
        self.dof_vel = rig.project(&cmd.velocity);
        self.ff = cmd.force;
    }

    /// The setpoint has been reached: it is the start of the next tick.
    #[inline]
    pub fn advance(&mut self) {
        self.prev_dof = self.dof;
        self.prev_dof_vel = self.dof_vel;
    }
}

impl Plate {
    /// Set `acc` for a substep of length `s`; `remaining` substeps in this
    /// tick including this one (the ideal model lands on the target at the
    /// end of the tick).
    // Called every substep with what varies per substep; the rest is `self`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
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
                // Tracking error in actuator space, mapped to plate DoF (the
                // map is linear, so the reference is interpolated after it).
                let q = rig.project_pose(&self.pose, self.sc);
                let qv = rig.project_twist(self.sc, &self.vel);
                let l = |a: [f64; 3], b: [f64; 3], i: usize| a[i] + (b[i] - a[i]) * fraction;
                let e: [f64; 3] = core::array::from_fn(|i| l(target.prev_dof, target.dof, i) - q[i]);
                let ed: [f64; 3] =
                    core::array::from_fn(|i| l(target.prev_dof_vel, target.dof_vel, i) - qv[i]);
                let inertia = [p.plate_mass, p.plate_mass, p.plate_inertia];
                let pd = Twist {
                    x: kp * e[0] + kd * ed[0],
                    y: kp * e[1] + kd * ed[1],
                    theta: kp * e[2] + kd * ed[2],
                };
                let mut f = [0.0; MAX_ACTUATORS];
                rig.feedforward_forces(&pd, &mut f);
                for (fi, ff) in f.iter_mut().zip(&target.ff) {
                    *fi += ff;
                }
                if noise > 0.0 {
                    for fi in &mut f[..p.count] {
                        *fi += noise * rng.normal();
                    }
                }
                // Every slot, masked (beyond `count` the force is 0 and the
                // limit unused): the loop has no variable bound.
                let mut sat = false;
                for (i, fi) in f.iter_mut().enumerate() {
                    let lim = p.actuators[i].max_force;
                    let over = (i < p.count) & (fi.abs() > lim);
                    sat |= over;
                    *fi = if over { lim.copysign(*fi) } else { *fi };
                }
                self.saturated += sat as u64;
                let q = rig.generalized_force_sc(self.sc, &f);
                self.acc = Twist { x: q[0] / inertia[0], y: q[1] / inertia[1], theta: q[2] / inertia[2] };
                self.force = f;
            }
        }
    }

    /// Integrate pose and velocity over `s` with the planned acceleration.
    #[inline(always)]
    pub fn integrate(&mut self, s: f64) {
        let a = self.acc;
        self.pose.x += self.vel.x * s + 0.5 * a.x * s * s;
        self.pose.y += self.vel.y * s + 0.5 * a.y * s * s;
        self.pose.theta += self.vel.theta * s + 0.5 * a.theta * s * s;
        self.vel.x += a.x * s;
        self.vel.y += a.y * s;
        self.vel.theta += a.theta * s;
        self.sc = sin_cos(self.pose.theta);
    }

    #[inline]
    pub fn set_pose(&mut self, pose: Pose) {
        self.pose = pose;
        self.sc = sin_cos(pose.theta);
    }
}
