//! Validated tunables of the core process. The TOML file is parsed in the
//! `upm-core` binary's crate; this is the typed, checked result.

use core::fmt;

use upm_motion::PartFriction;
use upm_motion::{InertiaParams, InertiaParamsError, MotionParams, ParamsError, RigError, RigParams};
use upm_motion::{PartDynamicsError, PartDynamicsParams};

/// Real-time placement of the threads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RtParams {
    /// SCHED_FIFO priority of the motor thread (1–99).
    pub motor_priority: u8,
    /// SCHED_FIFO priority of the solver thread (1–99, below the motor's).
    pub solver_priority: u8,
    /// CPU the motor thread is pinned to (`None`: not pinned).
    pub motor_cpu: Option<usize>,
    /// CPU the solver thread is pinned to.
    pub solver_cpu: Option<usize>,
    /// `mlockall` and prefault at start-up.
    pub lock_memory: bool,
    /// How the receiver thread waits for client messages.
    pub receiver: ReceiverWake,
    /// SCHED_FIFO priority of the receiver thread in `Event` mode (0 = normal
    /// scheduling; else 1–99, below the motor's). It then runs pinned to the
    /// motor's CPU: the motor preempts it, and it preempts neither the motor
    /// nor, on the other CPU, the solver. Not applied in `Spin` mode, where a
    /// real-time busy loop would starve its CPU.
    pub receiver_priority: u8,
    /// PM QoS request held on /dev/cpu_dma_latency for the core's life (µs
    /// an idle CPU may take to wake); `None` leaves the host's idle policy.
    pub cpu_dma_latency_us: Option<u32>,
    /// Keep the core's io thread off the motor's CPU (only the motor and
    /// the receiver, which the motor preempts, run there).
    pub isolate_motor_cpu: bool,
}

/// How the receiver thread learns of a client message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ReceiverWake {
    /// Sleep on the clients' wake-up event (a few µs of wake-up, no CPU
    /// burnt); clients that do not notify are seen at the next poll.
    #[default]
    Event,
    /// Busy-poll the subscribers: the lowest latency, one CPU kept busy.
    Spin,
}

impl Default for RtParams {
    fn default() -> Self {
        Self {
            motor_priority: 80,
            solver_priority: 70,
            motor_cpu: Some(1),
            solver_cpu: Some(0),
            lock_memory: true,
            receiver: ReceiverWake::Event,
            receiver_priority: 75,
            cpu_dma_latency_us: Some(0),
            isolate_motor_cpu: true,
        }
    }
}

/// Everything the core needs besides its driver.
#[derive(Debug, Clone, PartialEq)]
pub struct CoreParams {
    pub motion: MotionParams,
    pub rig: RigParams,
    /// A plate calibration's twist correction (`motion::Rig::with_correction`);
    /// None: the rig is its model.
    pub twist_correction: Option<[[f64; 3]; 3]>,
    /// Rotation centers (plate coordinates, m); schedules index into these.
    pub centers: Vec<[f64; 2]>,
    /// 0: a cycle plays every center once (the paper). N > 0: the centers
    /// are candidates and a cycle is N slots, allocated sparsely to the
    /// centers each request needs (`solver::sparse`).
    pub cycle_slots: usize,
    /// true: a part's rows are the friction wrench over the outline its
    /// `PartState` carries (`solver::shape`); false: every part is a point,
    /// the paper's model.
    pub part_shapes: bool,
    /// The solve stage's correction for each part's own velocity and spin
    /// (`part_dynamics.rs`); `steps = 0` turns it off.
    pub part_dynamics: PartDynamicsParams,
    /// Each part's friction as a plate calibration found it; read only by
    /// the part-dynamics correction (the calibrated planner divides
    /// requests by it; what online adaptation learns on top, the core does
    /// not see).
    pub part_friction: PartFriction,
    /// The motor loop's estimate of the plate's mass and inertia from the
    /// drives' servo effort, scaling the feed-forward
    /// (`motion::InertiaEstimate`); None: the feed-forward is the model's.
    pub inertia_adaptation: Option<InertiaParams>,
    /// μ·m·g of the parts (N): the scale of every requested force.
    pub mu_m_g: f64,
    /// PartStates older than this (by their stamp) put the core in hold.
    pub parts_max_age_ns: u64,
    /// Requests older than this (or past their own deadline) put the core in hold.
    pub request_max_age_ns: u64,
    /// How far a message stamp may be ahead of the core's clock.
    pub max_future_skew_ns: u64,
    /// Solver thread poll period.
    pub solver_poll_ns: u64,
    /// Telemetry publish period (io thread).
    pub telemetry_period_ns: u64,
    /// A driver-fault hold ends by itself after this long of healthy driver
    /// reads; 0 = only `upm resume` ends it.
    pub auto_resume_ns: u64,
    /// After a core thread dies, how long the core keeps publishing its
    /// health (plate held) before it exits with an error.
    pub fault_exit_ns: u64,
    pub rt: RtParams,
}

impl Default for CoreParams {
    /// The paper's 4-center rig at 10 kHz, 200 ms staleness.
    fn default() -> Self {
        Self {
            motion: MotionParams::default(),
            rig: RigParams::default(),
            twist_correction: None,
            centers: vec![[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]],
            cycle_slots: 0,
            part_shapes: true,
            part_dynamics: PartDynamicsParams::default(),
            part_friction: PartFriction::UNIFORM,
            inertia_adaptation: Some(InertiaParams::default()),
            mu_m_g: 0.1,
            parts_max_age_ns: 200_000_000,
            request_max_age_ns: 200_000_000,
            max_future_skew_ns: 1_000_000,
            solver_poll_ns: 500_000,
            telemetry_period_ns: 50_000_000,
            auto_resume_ns: 0,
            fault_exit_ns: 2_000_000_000,
            rt: RtParams::default(),
        }
    }
}

/// Why [`CoreParams::validate`] refused the configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CoreParamsError {
    Motion(ParamsError),
    Rig(RigError),
    PartDynamics(PartDynamicsError),
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
    MaxAge,
    SolverPoll,
    TelemetryPeriod,
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
            Self::PartDynamics(e) => write!(f, "{e}"),
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
            Self::MaxAge => f.write_str("safety: max ages must be positive"),
            Self::SolverPoll => f.write_str("rt.solver_poll_us must be positive"),
            Self::TelemetryPeriod => f.write_str("telemetry.period_ms must be positive"),
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
        if self.cycle_slots > 0 { self.cycle_slots } else { self.centers.len() }
    }

    pub fn validate(&self) -> Result<(), CoreParamsError> {
        self.motion.validate().map_err(CoreParamsError::Motion)?;
        self.rig.validate().map_err(CoreParamsError::Rig)?;
        self.part_dynamics.validate().map_err(CoreParamsError::PartDynamics)?;
        if let Some(p) = &self.inertia_adaptation {
            p.validate().map_err(CoreParamsError::InertiaAdaptation)?;
        }
        if self.twist_correction.is_some_and(|m| m.iter().flatten().any(|v| !v.is_finite())) {
            return Err(CoreParamsError::TwistCorrection);
        }
        if self.centers.is_empty() {
            return Err(CoreParamsError::NoCenters);
        }
        let capacity = ipc_types::MAX_CENTERS.min(upm_motion::MAX_SLOTS);
        if self.centers.len() > capacity {
            return Err(CoreParamsError::TooManyCenters { given: self.centers.len(), capacity });
        }
        if let Some(index) = self.centers.iter().position(|c| !(c[0].is_finite() && c[1].is_finite())) {
            return Err(CoreParamsError::NonFiniteCenter { index });
        }
        if !(self.mu_m_g.is_finite() && self.mu_m_g > 0.0) {
            return Err(CoreParamsError::MuMg);
        }
        if self.cycle_slots > capacity {
            return Err(CoreParamsError::CycleSlots { given: self.cycle_slots, capacity });
        }
        self.part_dynamics
            .trace_pieces(&self.motion, self.longest_cycle())
            .map_err(CoreParamsError::PartDynamics)?;
        if self.parts_max_age_ns == 0 || self.request_max_age_ns == 0 {
            return Err(CoreParamsError::MaxAge);
        }
        if self.solver_poll_ns == 0 {
            return Err(CoreParamsError::SolverPoll);
        }
        if self.telemetry_period_ns == 0 {
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
        let with = |cycle_slots| CoreParams { cycle_slots, ..CoreParams::default() }.validate();
        assert_eq!(with(0), Ok(()));
        assert_eq!(with(upm_motion::MAX_SLOTS), Ok(()));
        let e = with(upm_motion::MAX_SLOTS + 1).expect_err("too many");
        assert!(e.to_string().starts_with("motion.cycle_slots: 193 slots"), "{e}");
    }
}
