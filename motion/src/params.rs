//! Tunables of the plate motion and the limits it must respect.

use core::fmt;

use serde::{Deserialize, Serialize};

use crate::part_dynamics_params::{PartDynamicsError, PartDynamicsParams};

/// How slots are shaped.
/// `[motion]` of the rig file, read as it is: the plate's motion and the
/// hard limits it must respect (a schedule that needs more is refused,
/// [`super::MotionError`], never distorted), and how the core shapes its
/// cycles.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct MotionParams {
    /// Motor (sampling) rate, Hz.
    pub tick_hz: f64,
    /// Slot duration τ in ticks (slot boundaries fall on ticks).
    pub slot_ticks: u32,
    /// Peak displacement of the plate point farthest from the slot's center
    /// (m); sets the slot angle A_j = displacement / r_max,j.
    #[serde(rename = "displacement_mm", with = "upm_units::mm")]
    pub displacement: f64,
    /// Half-extent of the plate outline (m), plate centered on its origin:
    /// the file's `[plate] half_extent`.
    #[serde(skip)]
    pub plate_half_extent: [f64; 2],
    /// Ticks of the initial ramp of the slow half (rounded, ≥ 1).
    #[serde(skip)]
    pub ramp_up_ticks: u32,
    /// Ramps use this fraction of the acceleration limits (margin for the
    /// centripetal term and rounding).
    #[serde(skip)]
    pub ramp_fraction: f64,
    /// Bound on |k_j| accepted in a schedule (< 1: a slot needs a fast phase).
    pub k_max: f64,
    /// Peak rotation angle of a slot (rad).
    pub max_angle: f64,
    /// Peak angular velocity (rad/s).
    pub max_angular_velocity: f64,
    /// Peak angular acceleration (rad/s²).
    pub max_angular_acceleration: f64,
    /// Peak speed of any point of the plate outline (m/s).
    pub max_point_speed: f64,
    /// Peak acceleration (tangential and centripetal) of any plate point (m/s²).
    pub max_point_acceleration: f64,
    /// 0: a cycle plays every center once (the paper). N > 0: the centers
    /// are candidates and a cycle is N slots, allocated sparsely to the
    /// centers each request needs.
    pub cycle_slots: usize,
    /// true: a part's rows are the friction wrench over the outline its
    /// `PartState` carries; false: every part is a point (the paper).
    pub part_shapes: bool,
    /// The core's correction for each part's own velocity and spin;
    /// `steps = 0` turns it off.
    pub part_dynamics: PartDynamicsParams,
    /// The motor scales its feed-forward to the plate's mass and inertia
    /// as the drives' servo effort shows them; false: the model's. Unset:
    /// on with the simulator's drives, off with EtherCAT's (which exchange
    /// forces only every few ticks; asking for it there is an error).
    pub adapt_plate_inertia: Option<bool>,
}

impl Default for MotionParams {
    /// 10 kHz, τ = 4 ms (40 ticks), 2 mm peak displacement (at the plate
    /// corner farthest from the center; ~1–1.5 mm under the parts): plate
    /// speed at a part ≈ 0.3–1 m/s ≫ part speed ≈ μgτ ≈ 10 mm/s
    /// (Assumption 1), part travel per 4-slot cycle ≲ 1 mm (Assumption 2).
    /// The residual bias scales as μg·k·τ²/displacement (drag of the part's
    /// own velocity); BENCHMARKS.md, "`upm validate` on the paper's examples".
    fn default() -> Self {
        Self {
            tick_hz: 10_000.0,
            slot_ticks: 40,
            displacement: 2.0e-3,
            plate_half_extent: [1.0, 0.5],
            ramp_up_ticks: 1,
            ramp_fraction: 0.95,
            k_max: 0.95,
            // Generous (a light plate on voice coils): the fast phase of a
            // strongly asymmetric 4 ms slot needs thousands of m/s².
            max_angle: 0.01,
            max_angular_velocity: 20.0,
            max_angular_acceleration: 1.0e5,
            max_point_speed: 10.0,
            max_point_acceleration: 1.0e5,
            cycle_slots: 0,
            part_shapes: true,
            part_dynamics: PartDynamicsParams::default(),
            adapt_plate_inertia: None,
        }
    }
}

/// Why [`MotionParams::validate`] refused the parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamsError {
    TickRate,
    SlotTicks,
    Displacement,
    PlateExtent,
    RampUp,
    RampFraction,
    KMax,
    Limit,
    PartDynamics(PartDynamicsError),
}

impl fmt::Display for ParamsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            Self::PartDynamics(e) => return e.fmt(f),
            Self::TickRate => "motion.tick_hz must be finite and positive",
            Self::SlotTicks => "motion.slot_ticks must be at least 8",
            Self::Displacement => "motion.displacement_mm must be finite and positive",
            Self::PlateExtent => "plate.half_extent must be finite and positive",
            Self::RampUp => "motion.ramp_up_ticks must be at least 1",
            Self::RampFraction => "motion.ramp_fraction must be in (0, 1]",
            Self::KMax => "motion.k_max must be in (0, 1)",
            Self::Limit => {
                "motion: max_angle, max_angular_velocity, max_angular_acceleration, max_point_speed and max_point_acceleration must be finite and positive"
            }
        };
        f.write_str(s)
    }
}

impl core::error::Error for ParamsError {}

fn pos(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

impl MotionParams {
    pub fn validate(&self) -> Result<(), ParamsError> {
        if !pos(self.tick_hz) {
            return Err(ParamsError::TickRate);
        }
        if self.slot_ticks < 8 {
            return Err(ParamsError::SlotTicks);
        }
        if !pos(self.displacement) {
            return Err(ParamsError::Displacement);
        }
        if !pos(self.plate_half_extent[0]) || !pos(self.plate_half_extent[1]) {
            return Err(ParamsError::PlateExtent);
        }
        if self.ramp_up_ticks == 0 {
            return Err(ParamsError::RampUp);
        }
        if !(pos(self.ramp_fraction) && self.ramp_fraction <= 1.0) {
            return Err(ParamsError::RampFraction);
        }
        if !(pos(self.k_max) && self.k_max < 1.0) {
            return Err(ParamsError::KMax);
        }
        let limits = [
            self.max_angle,
            self.max_angular_velocity,
            self.max_angular_acceleration,
            self.max_point_speed,
            self.max_point_acceleration,
        ];
        if !limits.iter().all(|&x| pos(x)) {
            return Err(ParamsError::Limit);
        }
        self.part_dynamics.validate().map_err(ParamsError::PartDynamics)
    }

    /// Tick period (s).
    pub fn tick(&self) -> f64 {
        1.0 / self.tick_hz
    }

    /// Slot duration τ (s).
    pub fn slot_duration(&self) -> f64 {
        self.slot_ticks as f64 / self.tick_hz
    }
}
