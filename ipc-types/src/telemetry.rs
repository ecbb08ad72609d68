//! Telemetry: core → all, the core's state, counters and latencies.

use crate::header::{HeaderError, OldStamps, check_header};
use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::PROTOCOL_VERSION;
use crate::core_state::CoreState;
use crate::driver_telemetry::DriverTelemetry;
use crate::health::{HEALTH_DETAIL_BYTES, HealthCause, HealthSource, detail_str};
use crate::latency_percentiles::LatencyPercentiles;
use crate::reject_reason::REJECT_REASONS;
use crate::validation::{ValidationLimits, first_non_finite};

/// Monotonic counters since core start.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::CoreCounters.v6"))]
pub struct CoreCounters {
    /// Motor-loop ticks.
    pub ticks: u64,
    /// Ticks that woke up after their deadline.
    pub overruns: u64,
    /// Transitions into hold (stale input).
    pub hold_events: u64,
    /// Schedules made active at a cycle boundary.
    pub schedule_swaps: u64,
    /// PartStates messages that failed validation.
    pub rejected_parts: u64,
    /// ForceRequest / ExplicitSchedule messages that failed validation.
    pub rejected_requests: u64,
    /// Heap allocations seen on RT threads after start-up (should stay 0).
    pub rt_thread_allocations: u64,
    /// Driver reads or writes that reported a hardware fault.
    pub driver_faults: u64,
    /// Command entries the driver clamped to a limit (driver's own count).
    pub driver_clamped: u64,
    /// Commands the driver rejected as non-finite (driver's own count).
    pub driver_rejected: u64,
    /// Transitions into hold because of a driver fault.
    pub fault_holds: u64,
    /// Fault holds left, by `upm resume` or by auto-resume.
    pub resumes: u64,
}

const _: () = assert!(size_of::<CoreCounters>() == 12 * 8);

/// Latency of each measured path (ns, see [`LatencyPercentiles`]).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::CoreLatencies.v6"))]
pub struct CoreLatencies {
    /// Motor-thread wake-up lateness against its period.
    pub motor_wakeup: LatencyPercentiles,
    /// One solve.
    pub solver: LatencyPercentiles,
    /// PartStates stamp → received by the core.
    pub ipc_vision_to_core: LatencyPercentiles,
    /// Camera frame stamp → schedule ready.
    pub frame_to_schedule: LatencyPercentiles,
}

const _: () = assert!(size_of::<CoreLatencies>() == 4 * size_of::<LatencyPercentiles>());

/// Core → all: a snapshot of the core, published periodically.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::Telemetry.v6"))]
pub struct Telemetry {
    pub protocol_version: u32,
    /// [`CoreState`] code: idle 0, running 1, hold 2, fault 3.
    pub state: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns of the snapshot.
    pub stamp_ns: u64,
    /// Current motor cycle.
    pub cycle: u64,
    /// Commanded plate pose (m, m, rad) at the snapshot.
    pub plate_x: f64,
    pub plate_y: f64,
    pub plate_theta: f64,
    pub counters: CoreCounters,
    /// Age (ms) of the newest accepted PartStates; since core start if none
    /// was ever accepted. Finite, ≥ 0.
    pub parts_age_ms: f64,
    /// Age (ms) of the newest accepted request; same convention.
    pub request_age_ms: f64,
    pub latency: CoreLatencies,
    /// Process ids; 0 when the process is not known to be running.
    pub core_pid: u32,
    pub vision_pid: u32,
    pub planner_pid: u32,
    /// Real-time status bits: [`Telemetry::RT_MEMORY_LOCKED`] and friends.
    /// A core without privileges runs with some bits clear and says so.
    pub realtime_flags: u32,
    /// CLOCK_MONOTONIC ns when the vision / planner client started (its
    /// iceoryx2 node was created); 0 when absent.
    pub vision_started_ns: u64,
    pub planner_started_ns: u64,
    /// Rejected inbound messages by [`crate::RejectReason`] code.
    pub rejected_by_reason: [u64; REJECT_REASONS],
    /// [`HealthSource`] code: 0 = healthy.
    pub health_source: u32,
    /// [`HealthCause`] code.
    pub health_cause: u32,
    /// What happened, UTF-8, NUL-padded (e.g. where a thread panicked).
    pub health_detail: [u8; HEALTH_DETAIL_BYTES],
    /// The plate driver's bus state, faults and lost frames.
    pub driver: DriverTelemetry,
}

const _: () = assert!(
    size_of::<Telemetry>()
        == 4 + 4
            + 3 * 8
            + 3 * 8
            + size_of::<CoreCounters>()
            + 2 * 8
            + size_of::<CoreLatencies>()
            + 4 * 4
            + 2 * 8
            + REJECT_REASONS * 8
            + 2 * 4
            + HEALTH_DETAIL_BYTES
            + size_of::<DriverTelemetry>()
);

/// Why a [`Telemetry`] was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TelemetryError {
    /// Protocol version, count or stamp.
    Header(HeaderError),

    UnknownState {
        code: u32,
    },
    UnknownHealth {
        source: u32,
        cause: u32,
    },
    UnknownDriver {
        kind: u32,
        state: u32,
    },
    NonFinite {
        field: &'static str,
    },
    NegativeAge {
        field: &'static str,
    },
    /// p50 ≤ p99 ≤ p999 ≤ max does not hold for this latency.
    UnorderedPercentiles {
        field: &'static str,
    },
}

impl fmt::Display for TelemetryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("telemetry", f),
            Self::UnknownState { code } => write!(f, "telemetry.state {code} is not a known state code"),
            Self::UnknownHealth { source, cause } => {
                write!(f, "telemetry.health_source {source} / health_cause {cause} is not a known code")
            }
            Self::UnknownDriver { kind, state } => {
                write!(f, "telemetry.driver.kind {kind} / state {state} is not a known code")
            }
            Self::NonFinite { field } => write!(f, "telemetry.{field} is not finite"),
            Self::NegativeAge { field } => write!(f, "telemetry.{field} is negative"),
            Self::UnorderedPercentiles { field } => {
                write!(f, "telemetry.latency.{field} percentiles are not ordered p50 ≤ p99 ≤ p999 ≤ max")
            }
        }
    }
}

impl core::error::Error for TelemetryError {}

impl Telemetry {
    /// `mlockall` succeeded.
    pub const RT_MEMORY_LOCKED: u32 = 1;
    /// The motor thread runs SCHED_FIFO.
    pub const RT_MOTOR_FIFO: u32 = 2;
    /// The solver thread runs SCHED_FIFO.
    pub const RT_SOLVER_FIFO: u32 = 4;
    /// The counting allocator is installed: `rt_thread_allocations` is measured.
    pub const RT_ALLOCATIONS_COUNTED: u32 = 8;
    /// The motor thread is pinned to its CPU.
    pub const RT_MOTOR_PINNED: u32 = 16;
    /// The iceoryx2 receiver thread runs SCHED_FIFO on the motor's CPU.
    pub const RT_RECEIVER_FIFO: u32 = 32;
    /// The core holds a PM QoS request on /dev/cpu_dma_latency.
    pub const RT_PM_QOS_HELD: u32 = 64;

    /// Current protocol version, state idle, everything else 0.
    pub const fn new() -> Self {
        Self {
            protocol_version: PROTOCOL_VERSION,
            state: CoreState::Idle.code(),
            seq: 0,
            stamp_ns: 0,
            cycle: 0,
            plate_x: 0.0,
            plate_y: 0.0,
            plate_theta: 0.0,
            counters: CoreCounters {
                ticks: 0,
                overruns: 0,
                hold_events: 0,
                schedule_swaps: 0,
                rejected_parts: 0,
                rejected_requests: 0,
                rt_thread_allocations: 0,
                driver_faults: 0,
                driver_clamped: 0,
                driver_rejected: 0,
                fault_holds: 0,
                resumes: 0,
            },
            parts_age_ms: 0.0,
            request_age_ms: 0.0,
            latency: CoreLatencies {
                motor_wakeup: LatencyPercentiles::ZERO,
                solver: LatencyPercentiles::ZERO,
                ipc_vision_to_core: LatencyPercentiles::ZERO,
                frame_to_schedule: LatencyPercentiles::ZERO,
            },
            core_pid: 0,
            vision_pid: 0,
            planner_pid: 0,
            realtime_flags: 0,
            vision_started_ns: 0,
            planner_started_ns: 0,
            rejected_by_reason: [0; REJECT_REASONS],
            health_source: 0,
            health_cause: 0,
            health_detail: [0; HEALTH_DETAIL_BYTES],
            driver: DriverTelemetry::SIMULATED,
        }
    }

    /// Health source and cause, `None` for unknown codes.
    pub const fn health(&self) -> Option<(HealthSource, HealthCause)> {
        match (HealthSource::from_code(self.health_source), HealthCause::from_code(self.health_cause)) {
            (Some(s), Some(c)) => Some((s, c)),
            _ => None,
        }
    }

    /// The health detail as text (up to the first NUL or invalid byte).
    pub fn health_detail_str(&self) -> &str {
        detail_str(&self.health_detail)
    }

    /// The state, `None` if the code is unknown.
    pub const fn core_state(&self) -> Option<CoreState> {
        CoreState::from_code(self.state)
    }

    pub const fn set_core_state(&mut self, state: CoreState) {
        self.state = state.code();
    }

    /// Check the whole message; the first problem found is returned.
    /// Allocation-free, constant time.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), TelemetryError> {
        check_header(self.protocol_version, None, self.stamp_ns, OldStamps::Accept, limits)
            .map_err(TelemetryError::Header)?;
        if self.core_state().is_none() {
            return Err(TelemetryError::UnknownState { code: self.state });
        }
        if self.health().is_none() {
            return Err(TelemetryError::UnknownHealth {
                source: self.health_source,
                cause: self.health_cause,
            });
        }
        if self.driver.kind_str().is_none() || self.driver.state_str().is_none() {
            return Err(TelemetryError::UnknownDriver { kind: self.driver.kind, state: self.driver.state });
        }
        let floats = [
            ("plate_x", self.plate_x),
            ("plate_y", self.plate_y),
            ("plate_theta", self.plate_theta),
            ("parts_age_ms", self.parts_age_ms),
            ("request_age_ms", self.request_age_ms),
        ];
        if let Some(field) = first_non_finite(floats) {
            return Err(TelemetryError::NonFinite { field });
        }
        for (field, age) in [("parts_age_ms", self.parts_age_ms), ("request_age_ms", self.request_age_ms)] {
            if age < 0.0 {
                return Err(TelemetryError::NegativeAge { field });
            }
        }
        let l = &self.latency;
        let latencies = [
            ("motor_wakeup", l.motor_wakeup),
            ("solver", l.solver),
            ("ipc_vision_to_core", l.ipc_vision_to_core),
            ("frame_to_schedule", l.frame_to_schedule),
        ];
        for (field, p) in latencies {
            if !p.is_ordered() {
                return Err(TelemetryError::UnorderedPercentiles { field });
            }
        }
        Ok(())
    }
}

impl Default for Telemetry {
    fn default() -> Self {
        Self::new()
    }
}
