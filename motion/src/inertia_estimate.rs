//! The plate's mass and inertia as the drives show them, for the
//! feed-forward.
//!
//! Each drive applies the command's feed-forward force plus its own servo
//! effort. When the feed-forward is computed for the wrong plate (heavier
//! than the model, say), the servo makes up the difference, late: the plate
//! lags every fast phase, and a cycle's mean friction force, small against
//! the pushes that make it, moves by several percent. So each tick the
//! servo effort (measured force − sent feed-forward) is mapped to the
//! plate's (Fx, Fy, τ) and regressed on the feed-forward's own: translation
//! on (Fx, Fy), rotation on τ. At each cycle's end the scale s of each
//! moves to s·(1 + gain·β), β the cycle's regression slope, so it settles
//! where the servo effort no longer follows the feed-forward: the scale
//! the drives need, which also absorbs what sensor scale errors do to
//! the same forces.
//!
//! Not all servo effort is the plate's mass: a drive that interpolates
//! its position reference linearly through a tick, while the feed-forward
//! holds the tick's mean acceleration, pushes in phase with it even on an
//! exact plate (≈ 2 % of the feed-forward at 64 servo updates per tick,
//! none at one). So the estimate runs the drives' servo as specified
//! (`servo`, `servo_substeps`) on the model's plate alongside, and
//! regresses only the effort beyond what that exact plate would need.
//!
//! Robustness: a tick whose measured force is at a drive's limit (as the
//! driver reports it: a force averaged over the tick can hide a limit hit
//! in part of it), or whose command was clamped, is not used; a cycle with
//! too few ticks or too little feed-forward, or whose slope is not finite,
//! is skipped and counted; one cycle moves a scale by at most `max_step`,
//! and the scale stays within `min_scale..=max_scale`. Cost: two 3 × n
//! products per tick, and `servo_substeps` × 3 servo steps to predict it;
//! no allocation, no panic, no branch on data beyond those guards.

use core::fmt;

use super::actuator_command::MAX_ACTUATORS;
use super::plate_follow::PlateFollow;
use super::pose::{PlateSample, Pose};
use super::rig::Rig;
use crate::PlateState;

/// Tunables, with defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InertiaParams {
    /// Fraction of a cycle's slope taken per cycle.
    pub gain: f64,
    /// Largest change of a scale in one cycle (relative).
    pub max_step: f64,
    /// Bounds of each scale.
    pub min_scale: f64,
    pub max_scale: f64,
    /// Ticks a cycle must contribute before it updates anything.
    pub min_ticks: u64,
    /// The drives' position servo as specified, and its updates per motor
    /// tick (each on the reference interpolated linearly through the tick).
    pub servo: PlateFollow,
    pub servo_substeps: u32,
}

impl Default for InertiaParams {
    /// The simulator's drives at its default one update per tick.
    fn default() -> Self {
        Self {
            gain: 1.0,
            max_step: 0.05,
            min_scale: 0.5,
            max_scale: 2.0,
            min_ticks: 16,
            servo: PlateFollow::Servo { bandwidth_hz: 1000.0, damping: 0.7 },
            servo_substeps: 1,
        }
    }
}

/// Why [`InertiaParams::validate`] refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InertiaParamsError {
    Gain,
    MaxStep,
    Bounds,
    Servo,
}

impl fmt::Display for InertiaParamsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Gain => "inertia.gain must be finite, in (0, 2)",
            Self::MaxStep => "inertia.max_step must be finite, in (0, 0.5]",
            Self::Bounds => "inertia.min_scale / max_scale must be finite, 0 < min ≤ 1 ≤ max",
            Self::Servo => "inertia.servo: bandwidth and damping finite positive, 1..=1024 substeps",
        })
    }
}

impl core::error::Error for InertiaParamsError {}

impl InertiaParams {
    pub fn validate(&self) -> Result<(), InertiaParamsError> {
        if !(self.gain > 0.0 && self.gain < 2.0) {
            return Err(InertiaParamsError::Gain);
        }
        if !(self.max_step > 0.0 && self.max_step <= 0.5) {
            return Err(InertiaParamsError::MaxStep);
        }
        let ok = self.min_scale > 0.0 && self.min_scale <= 1.0 && self.max_scale >= 1.0;
        if !(ok && self.max_scale.is_finite()) {
            return Err(InertiaParamsError::Bounds);
        }
        let servo_ok = match self.servo {
            PlateFollow::Exact => true,
            PlateFollow::Servo { bandwidth_hz, damping } => {
                bandwidth_hz > 0.0 && bandwidth_hz.is_finite() && damping > 0.0 && damping.is_finite()
            }
        };
        if !(servo_ok && (1..=1024).contains(&self.servo_substeps)) {
            return Err(InertiaParamsError::Servo);
        }
        Ok(())
    }
}

/// The running estimate. `Copy`, fixed size, allocation-free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InertiaEstimate {
    params: InertiaParams,
    /// Σ u·u and Σ u·e for translation and rotation this cycle.
    uu: [f64; 2],
    ue: [f64; 2],
    ticks: u64,
    /// The driver's clamp count at the last tick.
    clamped: u64,
    /// The specified servo on an exact plate: pose and twist per DoF, and
    /// its mean acceleration effort over the tick last predicted.
    q: [f64; 3],
    qv: [f64; 3],
    expected: [f64; 3],
    scale: [f64; 2],
    updates: u64,
    skipped: u64,
}

impl InertiaEstimate {
    /// Starting from the model (scale 1), with `params` (validated by the
    /// caller; out-of-range values give a useless estimate, never a panic).
    pub fn new(params: InertiaParams) -> Self {
        Self {
            params,
            uu: [0.0; 2],
            ue: [0.0; 2],
            ticks: 0,
            clamped: 0,
            q: [0.0; 3],
            qv: [0.0; 3],
            expected: [0.0; 3],
            scale: [1.0; 2],
            updates: 0,
            skipped: 0,
        }
    }

    /// The tick about to be played, from setpoint `from` to `to` over
    /// `tick_s`: what servo effort (m/s², rad/s²) an exact plate needs in it.
    #[inline]
    pub fn predict(&mut self, from: &PlateSample, to: &PlateSample, tick_s: f64) {
        let PlateFollow::Servo { bandwidth_hz, damping } = self.params.servo else {
            return;
        };
        let w = core::f64::consts::TAU * bandwidth_hz;
        let (kp, kd) = (w * w, 2.0 * damping * w);
        let dof = |p: &PlateSample| {
            ([p.pose.x, p.pose.y, p.pose.theta], [p.velocity.x, p.velocity.y, p.velocity.theta])
        };
        let ((p0, v0), (p1, v1)) = (dof(from), dof(to));
        let n = self.params.servo_substeps.max(1);
        let s = tick_s / n as f64;
        let mut mean = [0.0; 3];
        // As a drive steps it: the effort from the state at each update's
        // start, held through the update.
        for k in 0..n {
            let f = k as f64 / n as f64;
            for i in 0..3 {
                let r = p0[i] + (p1[i] - p0[i]) * f;
                let rv = v0[i] + (v1[i] - v0[i]) * f;
                let pd = kp * (r - self.q[i]) + kd * (rv - self.qv[i]);
                let acc = (v1[i] - v0[i]) / tick_s + pd;
                mean[i] += pd / n as f64;
                self.q[i] += self.qv[i] * s + 0.5 * acc * s * s;
                self.qv[i] += acc * s;
            }
        }
        self.expected = mean;
    }

    /// One tick: `sent` was the feed-forward of the command the plate
    /// played to `pose`; `state` is the driver's reading after it (the
    /// force each drive applied, and its count of clamped entries).
    #[inline]
    pub fn observe(&mut self, rig: &Rig, pose: &Pose, sent: &[f64; MAX_ACTUATORS], state: &PlateState) {
        let clamped = state.clamped != self.clamped;
        self.clamped = state.clamped;
        let (p, measured) = (rig.params(), &state.actuator_force);
        let mut at_limit = clamped;
        let mut effort = [0.0; MAX_ACTUATORS];
        for i in 0..p.count {
            at_limit |= !(measured[i].abs() < p.actuators[i].max_force);
            effort[i] = measured[i] - sent[i];
        }
        if at_limit {
            return;
        }
        let u = rig.generalized_force(pose, sent);
        let mut e = rig.generalized_force(pose, &effort);
        // Beyond what the specified servo needs on the plate as estimated.
        let (m, i) = (p.plate_mass * self.scale[0], p.plate_inertia * self.scale[1]);
        let x = self.expected;
        e = [e[0] - m * x[0], e[1] - m * x[1], e[2] - i * x[2]];
        self.uu[0] += u[0] * u[0] + u[1] * u[1];
        self.ue[0] += u[0] * e[0] + u[1] * e[1];
        self.uu[1] += u[2] * u[2];
        self.ue[1] += u[2] * e[2];
        self.ticks += 1;
    }

    /// A cycle ended: update the scales from its ticks and start afresh.
    /// Returns the scales to command with.
    pub fn end_cycle(&mut self) -> [f64; 2] {
        let p = self.params;
        if self.ticks >= p.min_ticks {
            let mut used = false;
            for d in 0..2 {
                let beta = self.ue[d] / self.uu[d];
                if beta.is_finite() && self.uu[d] > 0.0 {
                    // max/min, not clamp: unvalidated bounds must not panic.
                    let step = (p.gain * beta).max(-p.max_step).min(p.max_step);
                    self.scale[d] = (self.scale[d] * (1.0 + step)).max(p.min_scale).min(p.max_scale);
                    used = true;
                }
            }
            if used {
                self.updates += 1;
            } else {
                self.skipped += 1;
            }
        } else if self.ticks > 0 {
            self.skipped += 1;
        }
        (self.uu, self.ue, self.ticks) = ([0.0; 2], [0.0; 2], 0);
        self.scale
    }

    /// A cycle was abandoned (hold): its ticks are not used, and the plate
    /// is brought home.
    pub fn discard_cycle(&mut self) {
        (self.uu, self.ue, self.ticks) = ([0.0; 2], [0.0; 2], 0);
        (self.q, self.qv, self.expected) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    }

    /// Mass and inertia over the model's.
    pub fn scale(&self) -> [f64; 2] {
        self.scale
    }

    /// Cycles that updated the scales, and cycles skipped (too few usable
    /// ticks, no feed-forward, or a slope that is not finite).
    pub fn updates(&self) -> u64 {
        self.updates
    }

    pub fn skipped(&self) -> u64 {
        self.skipped
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RigParams;

    fn rig() -> Rig {
        Rig::new(RigParams::default()).expect("rig")
    }

    /// Feed one cycle where every drive applies `ratio` × the sent force
    /// (a plate `ratio` times heavier, with a servo that keeps up).
    fn cycle(est: &mut InertiaEstimate, rig: &Rig, ratio: [f64; 2]) -> [f64; 2] {
        let mut model = rig.clone();
        model.set_inertia_scale([1.0; 2]);
        for t in 0..100 {
            let a = crate::Twist { x: (t as f64).sin(), y: (t as f64 * 0.7).cos(), theta: 0.3 };
            let mut sent = [0.0; MAX_ACTUATORS];
            rig.feedforward_forces(&a, &mut sent);
            let want = crate::Twist { x: a.x * ratio[0], y: a.y * ratio[0], theta: a.theta * ratio[1] };
            let mut state = PlateState::default();
            model.feedforward_forces(&want, &mut state.actuator_force);
            est.observe(rig, &Pose::HOME, &sent, &state);
        }
        est.end_cycle()
    }

    #[test]
    fn a_heavier_plate_is_found_and_the_estimate_stays_there() {
        let mut rig = rig();
        let mut est = InertiaEstimate::new(InertiaParams::default());
        let truth = [1.08, 0.93];
        for _ in 0..40 {
            let s = cycle(&mut est, &rig, truth);
            rig.set_inertia_scale(s);
        }
        let s = est.scale();
        assert!((s[0] - truth[0]).abs() < 1e-9 && (s[1] - truth[1]).abs() < 1e-9, "{s:?}");
        assert_eq!((est.updates(), est.skipped()), (40, 0));
    }

    #[test]
    fn a_cycle_moves_a_scale_by_at_most_max_step_within_bounds() {
        let rig = rig();
        let mut est = InertiaEstimate::new(InertiaParams::default());
        let s = cycle(&mut est, &rig, [3.0, 0.1]);
        assert_eq!(s, [1.05, 0.95]);
        for _ in 0..100 {
            cycle(&mut est, &rig, [3.0, 0.1]);
        }
        assert_eq!(est.scale(), [2.0, 0.5]);
    }

    #[test]
    fn forces_at_a_limit_and_empty_cycles_change_nothing_and_are_counted() {
        let rig = rig();
        let mut est = InertiaEstimate::new(InertiaParams::default());
        let sent = [1.0; MAX_ACTUATORS];
        let at = |force: f64, clamped: u64| PlateState {
            actuator_force: [force; MAX_ACTUATORS],
            clamped,
            ..PlateState::default()
        };
        for t in 0..100 {
            est.observe(&rig, &Pose::HOME, &sent, &at(rig.params().actuators[0].max_force, 0));
            est.observe(&rig, &Pose::HOME, &sent, &at(f64::NAN, 0));
            // A command the driver clamped: its force is not the one sent.
            est.observe(&rig, &Pose::HOME, &sent, &at(2.0, t + 1));
        }
        assert_eq!(est.end_cycle(), [1.0; 2]);
        // Enough ticks, but no feed-forward: the slope is not finite.
        for _ in 0..100 {
            est.observe(&rig, &Pose::HOME, &[0.0; MAX_ACTUATORS], &at(1.0, 100));
        }
        assert_eq!(est.end_cycle(), [1.0; 2]);
        assert_eq!((est.updates(), est.skipped()), (0, 1));
    }

    #[test]
    fn params_name_their_field() {
        assert!(InertiaParams::default().validate().is_ok());
        let bad = InertiaParams { gain: f64::NAN, ..InertiaParams::default() };
        assert_eq!(bad.validate(), Err(InertiaParamsError::Gain));
        let bad = InertiaParams { max_step: 0.0, ..InertiaParams::default() };
        assert_eq!(bad.validate(), Err(InertiaParamsError::MaxStep));
        let bad = InertiaParams { min_scale: 1.5, ..InertiaParams::default() };
        assert_eq!(bad.validate(), Err(InertiaParamsError::Bounds));
    }
}
