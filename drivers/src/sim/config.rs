//! Simulator configuration: what `[sim]` of the rig file sets is read
//! straight into [`SimConfig`]; the rest is the caller's.

use core::fmt;

use serde::{Deserialize, Serialize};

use upm_motion::{InertiaParams, PlateFollow, RigParams};

use super::truth::{PlateTruth, TruthError};

/// How the plate follows actuator commands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ActuatorModel {
    /// The plate reaches the commanded pose and velocity at the end of each
    /// tick, with constant acceleration during the tick.
    Ideal,
    /// A position servo per plate DoF (natural frequency `bandwidth_hz`,
    /// damping ratio `damping`) plus the command's feed-forward forces, each
    /// actuator force clamped to its limit; the plate is a rigid body.
    SecondOrder { bandwidth_hz: f64, damping: f64 },
}

/// `sim.actuator`: which [`ActuatorModel`] the plate follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ActuatorKind {
    Ideal,
    SecondOrder,
}

/// The fields the rig file does not set are `#[serde(skip)]`: the motor's
/// rate and the plate's extent come from `[motion]` and `[plate]`, the
/// truth from `[sim] truth`, the rest are the physics' constants.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimConfig {
    pub seed: u64,
    pub mu_static: f64,
    pub mu_kinetic: f64,
    pub actuator: ActuatorKind,
    /// The servo's natural frequency (`second_order`).
    pub bandwidth_hz: f64,
    /// The servo's damping ratio (`second_order`).
    pub damping: f64,
    /// Integration substeps per tick.
    pub substeps: u32,
    /// Driver tick rate (Hz); one `advance` = one tick.
    #[serde(skip)]
    pub tick_hz: f64,
    #[serde(skip)]
    pub gravity: f64,
    #[serde(skip)]
    pub rig: RigParams,
    /// Plate outline half-extent (m); the fence sits on this edge.
    #[serde(skip)]
    pub plate_half_extent: [f64; 2],
    #[serde(skip)]
    pub fence: bool,
    /// Restitution of part–fence and part–part impacts.
    #[serde(skip)]
    pub fence_restitution: f64,
    #[serde(skip)]
    pub part_restitution: f64,
    /// Part–part contact on/off (discs; polygons use their bounding circle).
    #[serde(skip)]
    pub collisions: bool,
    /// Std of white noise added to each actuator force (N), seeded.
    #[serde(skip)]
    pub force_noise: f64,
    /// How the plate really differs from `rig` and `mu_*` (only the
    /// simulator reads it).
    #[serde(skip)]
    pub truth: PlateTruth,
}

impl Default for SimConfig {
    /// Paper values μ = 0.25 (kinetic), static a bit higher; the plate
    /// servo at 1 kHz bandwidth with the motion's feed-forward.
    fn default() -> Self {
        Self {
            tick_hz: 10_000.0,
            substeps: 1,
            gravity: 9.81,
            mu_static: 0.3,
            mu_kinetic: 0.25,
            actuator: ActuatorKind::SecondOrder,
            bandwidth_hz: 1000.0,
            damping: 0.7,
            rig: RigParams::default(),
            plate_half_extent: [1.0, 0.5],
            fence: true,
            fence_restitution: 0.3,
            part_restitution: 0.5,
            collisions: true,
            force_noise: 0.0,
            seed: 0,
            truth: PlateTruth::NOMINAL,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SimConfigError {
    TickRate,
    Substeps,
    Gravity,
    Friction,
    Actuator,
    PlateExtent,
    Restitution,
    Noise,
    Truth(TruthError),
}

impl fmt::Display for SimConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::TickRate => "sim.tick_hz must be finite and positive",
            Self::Substeps => "sim.substeps must be in 1..=64",
            Self::Gravity => "sim.gravity must be finite and positive",
            Self::Friction => "sim: need 0 < mu_kinetic <= mu_static, both finite",
            Self::Actuator => "sim: bandwidth_hz and damping must be finite and positive",
            Self::PlateExtent => "sim.plate_half_extent must be finite and positive",
            Self::Restitution => "sim: restitutions must be in [0, 1]",
            Self::Noise => "sim.force_noise must be finite and >= 0",
            Self::Truth(e) => return write!(f, "{e}"),
        })
    }
}

impl core::error::Error for SimConfigError {}

impl SimConfig {
    /// How the plate follows its actuators.
    pub fn actuator_model(&self) -> ActuatorModel {
        match self.actuator {
            ActuatorKind::Ideal => ActuatorModel::Ideal,
            ActuatorKind::SecondOrder => {
                ActuatorModel::SecondOrder { bandwidth_hz: self.bandwidth_hz, damping: self.damping }
            }
        }
    }

    /// The motor's inertia estimate for these drives as specified (not as
    /// any hidden truth has the plate): their servo and its updates per tick.
    pub fn drive_servo(&self) -> InertiaParams {
        let servo = match self.actuator_model() {
            ActuatorModel::Ideal => PlateFollow::Exact,
            ActuatorModel::SecondOrder { bandwidth_hz, damping } => {
                PlateFollow::Servo { bandwidth_hz, damping }
            }
        };
        InertiaParams { servo, servo_substeps: self.substeps, ..InertiaParams::default() }
    }

    pub fn validate(&self) -> Result<(), SimConfigError> {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        if !pos(self.tick_hz) {
            return Err(SimConfigError::TickRate);
        }
        if !(1..=64).contains(&self.substeps) {
            return Err(SimConfigError::Substeps);
        }
        if !pos(self.gravity) {
            return Err(SimConfigError::Gravity);
        }
        if !(pos(self.mu_kinetic) && self.mu_static.is_finite() && self.mu_static >= self.mu_kinetic) {
            return Err(SimConfigError::Friction);
        }
        if self.actuator == ActuatorKind::SecondOrder && !(pos(self.bandwidth_hz) && pos(self.damping)) {
            return Err(SimConfigError::Actuator);
        }
        if !(pos(self.plate_half_extent[0]) && pos(self.plate_half_extent[1])) {
            return Err(SimConfigError::PlateExtent);
        }
        let unit = |x: f64| (0.0..=1.0).contains(&x);
        if !(unit(self.fence_restitution) && unit(self.part_restitution)) {
            return Err(SimConfigError::Restitution);
        }
        if !(self.force_noise.is_finite() && self.force_noise >= 0.0) {
            return Err(SimConfigError::Noise);
        }
        self.truth.validate(self.plate_half_extent).map_err(SimConfigError::Truth)?;
        Ok(())
    }
}
