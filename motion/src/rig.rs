//! Rig kinematics: plate pose ↔ actuator positions (ARCHITECTURE.md §6: four voice
//! coils, two along x and two along y). Linear actuators push along a fixed
//! world direction u_i at an attachment point a_i of the plate; the stroke is
//! the displacement of that point along u_i: s_i = u_i·(t + R(θ)a_i − a_i).

use core::fmt;

use super::plan::PlateMotion;
use super::pose::{PlateSample, Pose, Twist};
use crate::actuator_command::{ActuatorCommand, MAX_ACTUATORS};

/// One linear actuator and its limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Actuator {
    /// Attachment point in plate coordinates (m).
    pub attach: [f64; 2],
    /// Push direction (normalized by [`Rig::new`]).
    pub direction: [f64; 2],
    /// Stroke limit ±(m).
    pub stroke: f64,
    /// Velocity limit ±(m/s).
    pub max_velocity: f64,
    /// Force limit ±(N).
    pub max_force: f64,
}

impl Default for Actuator {
    fn default() -> Self {
        Self { attach: [0.0; 2], direction: [1.0, 0.0], stroke: 5e-3, max_velocity: 10.0, max_force: 2.0e4 }
    }
}

/// Rig geometry and plate inertia.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigParams {
    pub actuators: [Actuator; MAX_ACTUATORS],
    pub count: usize,
    /// Plate mass (kg) and moment of inertia about its origin (kg·m²): used
    /// for feed-forward forces.
    pub plate_mass: f64,
    pub plate_inertia: f64,
}

impl Default for RigParams {
    /// A 2 m × 1 m, 1 kg plate; x coils on the left edge at y = ±0.25 m,
    /// y coils on the bottom edge at x = ±0.5 m.
    fn default() -> Self {
        let mut actuators = [Actuator::default(); MAX_ACTUATORS];
        actuators[0] = Actuator { attach: [-1.0, 0.25], direction: [1.0, 0.0], ..Actuator::default() };
        actuators[1] = Actuator { attach: [-1.0, -0.25], direction: [1.0, 0.0], ..Actuator::default() };
        actuators[2] = Actuator { attach: [-0.5, -0.5], direction: [0.0, 1.0], ..Actuator::default() };
        actuators[3] = Actuator { attach: [0.5, -0.5], direction: [0.0, 1.0], ..Actuator::default() };
        Self { actuators, count: 4, plate_mass: 1.0, plate_inertia: 1.0 * (4.0 + 1.0) / 12.0 }
    }
}

/// Why a rig or a motion on it was refused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RigError {
    /// count not in 3..=MAX_ACTUATORS.
    Count,
    /// Non-finite or zero direction, non-finite attachment, non-positive limit.
    Actuator {
        actuator: usize,
    },
    /// Plate mass or inertia not finite positive.
    Inertia,
    /// The actuators cannot control all 3 DoF.
    Singular,
    StrokeLimit {
        actuator: usize,
        tick: u64,
        required: f64,
        limit: f64,
    },
    VelocityLimit {
        actuator: usize,
        tick: u64,
        required: f64,
        limit: f64,
    },
    ForceLimit {
        actuator: usize,
        tick: u64,
        required: f64,
        limit: f64,
    },
}

impl fmt::Display for RigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Count => write!(f, "rig.count must be between 3 and {MAX_ACTUATORS}"),
            Self::Actuator { actuator } => write!(f, "rig.actuators[{actuator}]: invalid geometry or limit"),
            Self::Inertia => write!(f, "rig.plate_mass / plate_inertia must be finite and positive"),
            Self::Singular => write!(f, "rig: actuators do not span x, y and θ"),
            Self::StrokeLimit { actuator, tick, required, limit } => {
                write!(f, "actuator {actuator} at tick {tick}: stroke {required:.3e} m > {limit:.3e}")
            }
            Self::VelocityLimit { actuator, tick, required, limit } => {
                write!(f, "actuator {actuator} at tick {tick}: velocity {required:.3e} m/s > {limit:.3e}")
            }
            Self::ForceLimit { actuator, tick, required, limit } => {
                write!(f, "actuator {actuator} at tick {tick}: force {required:.3e} N > {limit:.3e}")
            }
        }
    }
}

impl core::error::Error for RigError {}

impl RigParams {
    pub fn validate(&self) -> Result<(), RigError> {
        if !(3..=MAX_ACTUATORS).contains(&self.count) {
            return Err(RigError::Count);
        }
        for (i, a) in self.actuators[..self.count].iter().enumerate() {
            let n = a.direction[0].hypot(a.direction[1]);
            let finite = a.attach.iter().chain(&a.direction).all(|v| v.is_finite());
            let limits = [a.stroke, a.max_velocity, a.max_force].iter().all(|v| v.is_finite() && *v > 0.0);
            if !(finite && limits && n > 1e-12 && n.is_finite()) {
                return Err(RigError::Actuator { actuator: i });
            }
        }
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !(ok(self.plate_mass) && ok(self.plate_inertia)) {
            return Err(RigError::Inertia);
        }
        Ok(())
    }
}

/// Inverse of a symmetric 3×3 matrix, or None if (near) singular.
fn inv3(m: [[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    let c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    let c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    let det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    let scale = m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    if !(det.abs() > 1e-12 * scale * scale * scale) {
        return None;
    }
    let d = 1.0 / det;
    Some([
        [c00 * d, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * d, (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * d],
        [c01 * d, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * d, (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * d],
        [c02 * d, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * d, (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * d],
    ])
}

/// Validated rig with the pseudo-inverse of its home Jacobian precomputed.
#[derive(Debug, Clone)]
pub struct Rig {
    params: RigParams,
    /// The home Jacobian ∂s/∂(x, y, θ) transposed (one row per DoF), zero
    /// beyond `count`: the per-actuator maps run over every slot without a
    /// variable bound, so they vectorise.
    jt: [[f64; MAX_ACTUATORS]; 3],
    /// Per actuator, (pinv column, 0) and (J0 row, u·a): the sums over
    /// actuators accumulate four outputs in one register, in the same order
    /// as one sum per output.
    pinv_col: [[f64; 4]; MAX_ACTUATORS],
    force_col: [[f64; 4]; MAX_ACTUATORS],
    /// (JᵀJ)⁻¹Jᵀ, 3 × count.
    pinv: [[f64; MAX_ACTUATORS]; 3],
    /// u_i·a_i: how a rotation shortens actuator i beyond the linear term,
    /// s_i(x, y, θ) = J0_i·(x, y, sin θ) + (cos θ − 1)·u_i·a_i.
    radial: [f64; MAX_ACTUATORS],
    /// pinv · radial.
    radial_dof: [f64; 3],
    /// The twist to command for a wanted twist (a plate calibration's
    /// `twist_correction`, rows x, y, θ); None: the model is the plate.
    correction: Option<[[f64; 3]; 3]>,
    /// Feed-forward's plate mass and inertia over the model's
    /// ([`super::InertiaEstimate`]); 1 and 1: the model's.
    inertia_scale: [f64; 2],
}

impl Rig {
    pub fn new(mut params: RigParams) -> Result<Self, RigError> {
        params.validate()?;
        for a in &mut params.actuators[..params.count] {
            let n = a.direction[0].hypot(a.direction[1]);
            a.direction = [a.direction[0] / n, a.direction[1] / n];
        }
        let mut rig = Self {
            params,
            jt: [[0.0; MAX_ACTUATORS]; 3],
            pinv_col: [[0.0; 4]; MAX_ACTUATORS],
            force_col: [[0.0; 4]; MAX_ACTUATORS],
            pinv: [[0.0; MAX_ACTUATORS]; 3],
            radial: [0.0; MAX_ACTUATORS],
            radial_dof: [0.0; 3],
            correction: None,
            inertia_scale: [1.0; 2],
        };
        // Rows of the home Jacobian; only the layouts derived from it are kept.
        let mut jac = [[0.0; 3]; MAX_ACTUATORS];
        let mut jtj = [[0.0; 3]; 3];
        for i in 0..params.count {
            jac[i] = rig.jacobian_row(i, 0.0);
            for r in 0..3 {
                rig.jt[r][i] = jac[i][r];
            }
            for r in 0..3 {
                for c in 0..3 {
                    jtj[r][c] += jac[i][r] * jac[i][c];
                }
            }
        }
        let inv = inv3(jtj).ok_or(RigError::Singular)?;
        for r in 0..3 {
            for i in 0..params.count {
                rig.pinv[r][i] = (0..3).map(|c| inv[r][c] * jac[i][c]).sum();
            }
        }
        for (r, a) in rig.radial.iter_mut().zip(&params.actuators[..params.count]) {
            *r = a.direction[0] * a.attach[0] + a.direction[1] * a.attach[1];
        }
        for i in 0..params.count {
            rig.pinv_col[i] = [rig.pinv[0][i], rig.pinv[1][i], rig.pinv[2][i], 0.0];
            rig.force_col[i] = [jac[i][0], jac[i][1], jac[i][2], rig.radial[i]];
        }
        rig.radial_dof = rig.project(&rig.radial);
        Ok(rig)
    }

    pub fn params(&self) -> &RigParams {
        &self.params
    }

    /// This rig, commanding `correction`·ξ for every wanted pose, twist and
    /// acceleration ξ of a motion ([`Rig::command`]): a calibrated plate
    /// that turns about a shifted center is told to turn about one that
    /// lands it where the model wants. Small-motion (linear) correction.
    pub fn with_correction(mut self, correction: [[f64; 3]; 3]) -> Self {
        self.correction = Some(correction);
        self
    }

    pub fn correction(&self) -> Option<&[[f64; 3]; 3]> {
        self.correction.as_ref()
    }

    /// Feed-forward forces for a plate `scale[0]` times the model's mass and
    /// `scale[1]` times its inertia (what the drives show it to be). Only
    /// the feed-forward changes: kinematics and limits stay the model's.
    /// A value that is not finite and positive counts as 1.
    pub fn set_inertia_scale(&mut self, scale: [f64; 2]) {
        self.inertia_scale = scale.map(|s| if s.is_finite() && s > 0.0 { s } else { 1.0 });
    }

    pub fn inertia_scale(&self) -> [f64; 2] {
        self.inertia_scale
    }

    pub fn count(&self) -> usize {
        self.params.count
    }

    /// ∂s_i/∂(x, y, θ) at angle θ.
    #[inline]
    fn jacobian_row(&self, i: usize, theta: f64) -> [f64; 3] {
        self.jacobian_row_sc(i, super::pose::sin_cos(theta))
    }

    /// Same, with (sin θ, cos θ) precomputed.
    #[inline]
    fn jacobian_row_sc(&self, i: usize, (s, c): (f64, f64)) -> [f64; 3] {
        let a = &self.params.actuators[i];
        let ra = [c * a.attach[0] - s * a.attach[1], s * a.attach[0] + c * a.attach[1]];
        let u = a.direction;
        [u[0], u[1], -u[0] * ra[1] + u[1] * ra[0]]
    }

    /// Actuator positions for a pose (exact, nonlinear).
    #[inline]
    pub fn actuator_positions(&self, pose: &Pose, out: &mut [f64; MAX_ACTUATORS]) {
        self.actuator_positions_sc(pose, super::pose::sin_cos(pose.theta), out);
    }

    /// Same, with (sin θ, cos θ) of the pose precomputed.
    #[inline]
    pub fn actuator_positions_sc(&self, pose: &Pose, (s, c): (f64, f64), out: &mut [f64; MAX_ACTUATORS]) {
        // s_i = J0_i·(x, y, sin θ) + (cos θ − 1)·u_i·a_i, the same as
        // u_i·(t + R(θ)a_i − a_i).
        let (k, j) = (c - 1.0, &self.jt);
        for i in 0..MAX_ACTUATORS {
            out[i] = j[0][i] * pose.x + j[1][i] * pose.y + j[2][i] * s + k * self.radial[i];
        }
    }

    /// Actuator velocities for a pose and plate twist.
    #[inline]
    pub fn actuator_velocities(&self, pose: &Pose, v: &Twist, out: &mut [f64; MAX_ACTUATORS]) {
        self.actuator_velocities_sc(super::pose::sin_cos(pose.theta), v, out);
    }

    /// Same, with (sin θ, cos θ) of the pose precomputed.
    #[inline]
    pub fn actuator_velocities_sc(&self, (s, c): (f64, f64), v: &Twist, out: &mut [f64; MAX_ACTUATORS]) {
        // J(θ)_i = (u_x, u_y, cos θ·J0_i2 − sin θ·u_i·a_i).
        let (cw, sw, j) = (c * v.theta, s * v.theta, &self.jt);
        for i in 0..MAX_ACTUATORS {
            out[i] = j[0][i] * v.x + j[1][i] * v.y + j[2][i] * cw - sw * self.radial[i];
        }
    }

    /// `project(actuator_positions(pose))` in closed form (O(1), no loop):
    /// (x + (c−1)·r₀, y + (c−1)·r₁, sin θ + (c−1)·r₂) with r = pinv·(u·a).
    #[inline]
    pub fn project_pose(&self, pose: &Pose, (s, c): (f64, f64)) -> [f64; 3] {
        let (k, r) = (c - 1.0, &self.radial_dof);
        [pose.x + k * r[0], pose.y + k * r[1], s + k * r[2]]
    }

    /// `project(actuator_velocities(pose, v))` in closed form:
    /// (vx, vy, cos θ·ω) − sin θ·ω·r with r = pinv·(u·a).
    #[inline]
    pub fn project_twist(&self, (s, c): (f64, f64), v: &Twist) -> [f64; 3] {
        let (k, r) = (s * v.theta, &self.radial_dof);
        [v.x - k * r[0], v.y - k * r[1], c * v.theta - k * r[2]]
    }

    /// Linearised plate DoF of an actuator-space vector: the home
    /// pseudo-inverse applied to it (exact at home, error ~|θ| elsewhere).
    /// This is what a servo closed on the actuator encoders sees.
    #[inline]
    pub fn project(&self, s: &[f64; MAX_ACTUATORS]) -> [f64; 3] {
        let mut d = [0.0; 4];
        for (col, &si) in self.pinv_col.iter().zip(s).take(self.params.count) {
            for r in 0..4 {
                d[r] += col[r] * si;
            }
        }
        [d[0], d[1], d[2]]
    }

    /// Pose from actuator positions: least squares over all actuators,
    /// Gauss–Newton with the precomputed home pseudo-inverse (converges by a
    /// factor ~|θ| per iteration; 3 iterations, bounded work). Exactly home
    /// when all positions are 0.
    #[inline]
    pub fn pose_from_actuators(&self, s: &[f64; MAX_ACTUATORS]) -> Pose {
        let mut q = Pose::HOME;
        let mut fwd = [0.0; MAX_ACTUATORS];
        for _ in 0..3 {
            self.actuator_positions(&q, &mut fwd);
            let mut d = [0.0; 3];
            for i in 0..self.params.count {
                let r = s[i] - fwd[i];
                for (dk, pk) in d.iter_mut().zip(&self.pinv) {
                    *dk += pk[i] * r;
                }
            }
            q.x += d[0];
            q.y += d[1];
            q.theta += d[2];
        }
        q
    }

    /// Plate twist from actuator velocities at a pose: the home
    /// pseudo-inverse refined twice against the Jacobian at that pose
    /// (error ~|θ|³, no matrix inverse on the hot path).
    #[inline]
    pub fn twist_from_actuators(&self, pose: &Pose, sdot: &[f64; MAX_ACTUATORS]) -> Twist {
        let sc = super::pose::sin_cos(pose.theta);
        let n = self.params.count;
        let mut v = [0.0; 3];
        for _ in 0..3 {
            let mut d = [0.0; 3];
            for i in 0..n {
                let j = self.jacobian_row_sc(i, sc);
                let r = sdot[i] - (j[0] * v[0] + j[1] * v[1] + j[2] * v[2]);
                for (dk, pk) in d.iter_mut().zip(&self.pinv) {
                    *dk += pk[i] * r;
                }
            }
            for k in 0..3 {
                v[k] += d[k];
            }
        }
        Twist { x: v[0], y: v[1], theta: v[2] }
    }

    /// Exact least-squares twist (normal equations at the pose).
    pub fn twist_from_actuators_exact(&self, pose: &Pose, sdot: &[f64; MAX_ACTUATORS]) -> Twist {
        let mut jtj = [[0.0; 3]; 3];
        let mut jts = [0.0; 3];
        let sc = super::pose::sin_cos(pose.theta);
        for (i, &sd) in sdot.iter().enumerate().take(self.params.count) {
            let j = self.jacobian_row_sc(i, sc);
            for r in 0..3 {
                jts[r] += j[r] * sd;
                for c in 0..3 {
                    jtj[r][c] += j[r] * j[c];
                }
            }
        }
        match inv3(jtj) {
            Some(m) => {
                let v: [f64; 3] = core::array::from_fn(|r| (0..3).map(|c| m[r][c] * jts[c]).sum());
                Twist { x: v[0], y: v[1], theta: v[2] }
            }
            None => Twist::default(),
        }
    }

    /// Minimum-norm actuator forces that give the plate this acceleration
    /// (feed-forward; home Jacobian, parts' reaction neglected).
    #[inline]
    pub fn feedforward_forces(&self, acc: &Twist, out: &mut [f64; MAX_ACTUATORS]) {
        // × 1.0 is exact: an unscaled rig gives the model's bits.
        let [sm, si] = self.inertia_scale;
        let (m, i) = (self.params.plate_mass * sm, self.params.plate_inertia * si);
        let q = [m * acc.x, m * acc.y, i * acc.theta];
        // pinv is zero beyond `count`, so those forces come out 0.
        for i in 0..MAX_ACTUATORS {
            out[i] = self.pinv[0][i] * q[0] + self.pinv[1][i] * q[1] + self.pinv[2][i] * q[2];
        }
    }

    /// Generalized force (Fx, Fy, torque) of actuator forces at a pose.
    #[inline]
    pub fn generalized_force(&self, pose: &Pose, f: &[f64; MAX_ACTUATORS]) -> [f64; 3] {
        self.generalized_force_sc(super::pose::sin_cos(pose.theta), f)
    }

    /// Same, with (sin θ, cos θ) of the pose precomputed.
    #[inline]
    pub fn generalized_force_sc(&self, (s, c): (f64, f64), f: &[f64; MAX_ACTUATORS]) -> [f64; 3] {
        // J(θ)_i = (u_x, u_y, cos θ·J0_i2 − sin θ·u_i·a_i).
        let mut q = [0.0; 4];
        for (col, &fi) in self.force_col.iter().zip(f).take(self.params.count) {
            for r in 0..4 {
                q[r] += col[r] * fi;
            }
        }
        [q[0], q[1], c * q[2] - s * q[3]]
    }

    /// The command that plays one motion sample: positions, velocities and
    /// feed-forward forces. Allocation-free.
    #[inline(always)]
    pub fn command(&self, sample: &PlateSample, cmd: &mut ActuatorCommand) {
        let corrected;
        let sample = match &self.correction {
            Some(m) => {
                let map = |v: [f64; 3]| {
                    core::array::from_fn::<f64, 3, _>(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
                };
                let (p, v, a) = (sample.pose, sample.velocity, sample.acceleration);
                let [px, py, pt] = map([p.x, p.y, p.theta]);
                let [vx, vy, vt] = map([v.x, v.y, v.theta]);
                let [ax, ay, at] = map([a.x, a.y, a.theta]);
                corrected = PlateSample {
                    pose: Pose { x: px, y: py, theta: pt },
                    velocity: Twist { x: vx, y: vy, theta: vt },
                    acceleration: Twist { x: ax, y: ay, theta: at },
                    ..*sample
                };
                &corrected
            }
            None => sample,
        };
        let sc = super::pose::sin_cos(sample.pose.theta);
        self.actuator_positions_sc(&sample.pose, sc, &mut cmd.position);
        self.actuator_velocities_sc(sc, &sample.velocity, &mut cmd.velocity);
        self.feedforward_forces(&sample.acceleration, &mut cmd.force);
        for i in self.params.count..MAX_ACTUATORS {
            cmd.position[i] = 0.0;
            cmd.velocity[i] = 0.0;
            cmd.force[i] = 0.0;
        }
    }

    /// Check every tick of one cycle of `motion` against the actuator limits.
    pub fn check_motion(&self, motion: &PlateMotion) -> Result<(), RigError> {
        let mut cmd = ActuatorCommand::default();
        for tick in 0..motion.cycle_ticks() {
            self.command(&motion.sample_tick(tick), &mut cmd);
            for (i, a) in self.params.actuators[..self.params.count].iter().enumerate() {
                let checks = [
                    (cmd.position[i], a.stroke, 0),
                    (cmd.velocity[i], a.max_velocity, 1),
                    (cmd.force[i], a.max_force, 2),
                ];
                for (v, lim, kind) in checks {
                    if v.abs() > lim {
                        let (actuator, required, limit) = (i, v.abs(), lim);
                        return Err(match kind {
                            0 => RigError::StrokeLimit { actuator, tick, required, limit },
                            1 => RigError::VelocityLimit { actuator, tick, required, limit },
                            _ => RigError::ForceLimit { actuator, tick, required, limit },
                        });
                    }
                }
            }
        }
        Ok(())
    }
}
