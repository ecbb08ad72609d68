//! The core process's tunables, checked. Each section of the rig file is
//! read straight into its type here; the `upm-core` binary's crate reads
//! the file and adds what a calibration says.

use core::fmt;

use upm_motion::PartFriction;
use upm_motion::{InertiaParams, InertiaParamsError, MotionParams, ParamsError, RigError, RigParams};

use crate::plate_params::PlateParams;
use crate::rt_params::RtParams;
use crate::safety_params::{SafetyError, SafetyParams, TelemetryParams};

/// Everything the core needs besides its driver: the rig file's core
/// sections, read as they are, and what a calibration adds.
#[derive(Debug, Clone, PartialEq)]
pub struct CoreParams {
    /// `[plate]`.
    pub plate: PlateParams,
    /// `[motion]`; its `plate_half_extent` is `plate.half_extent`.
    pub motion: MotionParams,
    /// `[rt]`.
    pub rt: RtParams,
    /// `[safety]`.
    pub safety: SafetyParams,
    /// `[telemetry]`.
    pub telemetry: TelemetryParams,
    pub rig: RigParams,
    /// A plate calibration's twist correction (`motion::Rig::with_correction`);
    /// None: the rig is its model.
    pub twist_correction: Option<[[f64; 3]; 3]>,
    /// Each part's friction as a plate calibration found it; read only by
    /// the part-dynamics correction (the calibrated planner divides
    /// requests by it; what online adaptation learns on top, the core does
    /// not see).
    pub part_friction: PartFriction,
    /// The motor loop's estimate of the plate's mass and inertia from the
    /// drives' servo effort, scaling the feed-forward
    /// (`motion::InertiaEstimate`); None: the feed-forward is the model's.
    pub inertia_adaptation: Option<InertiaParams>,
}

impl Default for CoreParams {
    /// The paper's 4-center rig at 10 kHz, 200 ms staleness.
    fn default() -> Self {
        let plate = PlateParams::default();
        Self {
            motion: MotionParams { plate_half_extent: plate.half_extent, ..MotionParams::default() },
            plate,
            rt: RtParams::default(),
            safety: SafetyParams::default(),
            telemetry: TelemetryParams::default(),
            rig: RigParams::default(),
            twist_correction: None,
            part_friction: PartFriction::UNIFORM,
            inertia_adaptation: Some(InertiaParams::default()),
        }
    }
}

/// Why [`CoreParams::validate`] refused the configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CoreParamsError {
    Motion(ParamsError),
    Rig(RigError),
    InertiaAdaptation(InertiaParamsError),
    NoCenters,
    TooManyCenters {
        given: usize,
        capacity: usize,
    },
    NonFiniteCenter {
        index: usize,
    },
    MuMg,
    /// A twist correction with a non-finite entry.
    TwistCorrection,
    CycleSlots {
        given: usize,
        capacity: usize,
    },
    Safety(SafetyError),
    SolverPoll,
    /// Telemetry is published at most once a millisecond.
    TelemetryPeriod,
    /// `motion.plate_half_extent` is not `plate.half_extent`.
    PlateExtentMismatch,
    Priority,
    ReceiverPriority,
    /// A center cannot play any k within the motion and actuator limits.
    Unplayable {
        center: usize,
    },
}

impl fmt::Display for CoreParamsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Motion(e) => write!(f, "{e}"),
            Self::Rig(e) => write!(f, "rig: {e}"),
            Self::InertiaAdaptation(e) => write!(f, "{e}"),
            Self::NoCenters => f.write_str("plate.centers: at least one rotation center is needed"),
            Self::TooManyCenters { given, capacity } => {
                write!(f, "plate.centers: {given} centers, capacity is {capacity}")
            }
            Self::NonFiniteCenter { index } => write!(f, "plate.centers[{index}] is not finite"),
            Self::MuMg => f.write_str("plate.mu_m_g must be finite and positive"),
            Self::TwistCorrection => f.write_str("the calibration's twist_correction must be finite"),
            Self::CycleSlots { given, capacity } => {
                write!(
                    f,
                    "motion.cycle_slots: {given} slots, capacity is {capacity} (0: one slot per center)"
                )
            }
            Self::Safety(e) => write!(f, "{e}"),
            Self::SolverPoll => f.write_str("rt.solver_poll_us must be positive"),
            Self::TelemetryPeriod => f.write_str("telemetry.period_ms must be at least 1"),
            Self::PlateExtentMismatch => f.write_str("motion.plate_half_extent must be plate.half_extent"),
            Self::Unplayable { center } => write!(
                f,
                "centers[{center}]: cannot play any k within the motion and actuator limits \
                 (raise motion.slot_ticks or the limits, or lower motion.displacement_mm)"
            ),
            Self::Priority => {
                f.write_str("rt: priorities must be in 1..=99 and the motor's above the solver's")
            }
            Self::ReceiverPriority => f.write_str(
                "rt.receiver_priority must be 0 (normal scheduling) or in 1..=99 below the motor's",
            ),
        }
    }
}

impl core::error::Error for CoreParamsError {}

impl CoreParams {
    /// Slots of the longest cycle a request can be given.
    pub fn longest_cycle(&self) -> usize {
        if self.motion.cycle_slots > 0 { self.motion.cycle_slots } else { self.plate.centers.len() }
    }

    pub fn validate(&self) -> Result<(), CoreParamsError> {
        self.motion.validate().map_err(CoreParamsError::Motion)?;
        if self.motion.plate_half_extent != self.plate.half_extent {
            return Err(CoreParamsError::PlateExtentMismatch);
        }
        self.rig.validate().map_err(CoreParamsError::Rig)?;
        if let Some(p) = &self.inertia_adaptation {
            p.validate().map_err(CoreParamsError::InertiaAdaptation)?;
        }
        if self.twist_correction.is_some_and(|m| m.iter().flatten().any(|v| !v.is_finite())) {
            return Err(CoreParamsError::TwistCorrection);
        }
        let centers = &self.plate.centers;
        if centers.is_empty() {
            return Err(CoreParamsError::NoCenters);
        }
        let capacity = ipc_types::MAX_CENTERS.min(upm_motion::MAX_SLOTS);
        if centers.len() > capacity {
            return Err(CoreParamsError::TooManyCenters { given: centers.len(), capacity });
        }
        if let Some(index) = centers.iter().position(|c| !(c[0].is_finite() && c[1].is_finite())) {
            return Err(CoreParamsError::NonFiniteCenter { index });
        }
        if !(self.plate.mu_m_g.is_finite() && self.plate.mu_m_g > 0.0) {
            return Err(CoreParamsError::MuMg);
        }
        if self.motion.cycle_slots > capacity {
            return Err(CoreParamsError::CycleSlots { given: self.motion.cycle_slots, capacity });
        }
        self.motion
            .part_dynamics
            .trace_pieces(&self.motion, self.longest_cycle())
            .map_err(|e| CoreParamsError::Motion(ParamsError::PartDynamics(e)))?;
        self.safety.validate().map_err(CoreParamsError::Safety)?;
        if self.rt.solver_poll_ns == 0 {
            return Err(CoreParamsError::SolverPoll);
        }
        if self.telemetry.period_ns < 1_000_000 {
            return Err(CoreParamsError::TelemetryPeriod);
        }
        let rt = &self.rt;
        let ok = |p: u8| (1..=99).contains(&p);
        if !(ok(rt.motor_priority) && ok(rt.solver_priority) && rt.motor_priority > rt.solver_priority) {
            return Err(CoreParamsError::Priority);
        }
        if rt.receiver_priority != 0
            && !(ok(rt.receiver_priority) && rt.receiver_priority < rt.motor_priority)
        {
            return Err(CoreParamsError::ReceiverPriority);
        }
        Ok(())
    }

    /// Everything [`Self::validate`] checks, plus that every center can play
    /// some k within the motion and actuator limits. Returns, per center,
    /// the bound on |k| the core will actually use.
    pub fn playable_k_bounds(&self) -> Result<Vec<f64>, CoreParamsError> {
        self.validate()?;
        playable_k_bounds(self, &self.plate_rig()?)
    }

    /// The rig the motor commands: `rig`, through the calibration's
    /// correction if there is one.
    pub fn plate_rig(&self) -> Result<upm_motion::Rig, CoreParamsError> {
        let rig = upm_motion::Rig::new(self.rig).map_err(CoreParamsError::Rig)?;
        Ok(match self.twist_correction {
            Some(m) => rig.with_correction(m),
            None => rig,
        })
    }

    /// Motor tick period (ns).
    pub fn tick_ns(&self) -> u64 {
        (1e9 / self.motion.tick_hz).round() as u64
    }
}

/// Per center, the largest |k| ≤ `motion.k_max` it can play within the
/// motion limits and the actuators' stroke, velocity and force limits
/// ([`playable_k`]). Slots are independent (each tick belongs to one slot),
/// so a schedule whose every |k_j| is within its center's bound passes
/// [`Rig::check_motion`]. Bisection, at start-up only.
pub(crate) fn playable_k_bounds(
    params: &CoreParams,
    rig: &upm_motion::Rig,
) -> Result<Vec<f64>, CoreParamsError> {
    let mut probe = upm_motion::PlateMotion::new(params.motion).map_err(CoreParamsError::Motion)?;
    let bounds: Vec<f64> = params
        .plate
        .centers
        .iter()
        .map(|&c| upm_motion::playable_k(&mut probe, rig, c, params.motion.k_max))
        .collect();
    if let Some(center) = bounds.iter().position(|&k| k.is_nan() || k <= 0.0) {
        return Err(CoreParamsError::Unplayable { center });
    }
    Ok(bounds)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with_receiver_priority(p: u8) -> Result<(), CoreParamsError> {
        let mut params = CoreParams::default();
        params.rt.receiver_priority = p;
        params.validate()
    }

    #[test]
    fn receiver_priority_is_zero_or_below_the_motor() {
        assert_eq!(with_receiver_priority(0), Ok(()));
        assert_eq!(with_receiver_priority(75), Ok(()));
        assert_eq!(with_receiver_priority(79), Ok(()));
        assert_eq!(with_receiver_priority(80), Err(CoreParamsError::ReceiverPriority));
        assert_eq!(with_receiver_priority(100), Err(CoreParamsError::ReceiverPriority));
    }

    #[test]
    fn cycle_slots_fit_a_schedule() {
        let with = |cycle_slots| {
            let mut params = CoreParams::default();
            params.motion.cycle_slots = cycle_slots;
            params.validate()
        };
        assert_eq!(with(0), Ok(()));
        assert_eq!(with(upm_motion::MAX_SLOTS), Ok(()));
        let e = with(upm_motion::MAX_SLOTS + 1).expect_err("too many");
        assert!(e.to_string().starts_with("motion.cycle_slots: 193 slots"), "{e}");
    }
}
