//! State the threads share through atomics only (no locks): counters,
//! the operating state, the stamps staleness is judged on, the commanded
//! plate pose and the core's health. Values are individually consistent,
//! not a snapshot.

use core::fmt::Write;
use core::sync::atomic::{
    AtomicBool, AtomicU8, AtomicU32, AtomicU64, Ordering::Acquire, Ordering::Relaxed, Ordering::Release,
};

use ipc_types::{
    CoreCounters, CoreState, DetailText, HEALTH_DETAIL_BYTES, HealthCause, HealthSource, REJECT_REASONS,
    RejectReason,
};

use upm_motion::Pose;

#[derive(Debug, Default)]
pub struct CoreShared {
    state: AtomicU32,
    pub cycle: AtomicU64,
    pub ticks: AtomicU64,
    pub overruns: AtomicU64,
    pub hold_events: AtomicU64,
    pub schedule_swaps: AtomicU64,
    pub rejected_parts: AtomicU64,
    pub rejected_requests: AtomicU64,
    rejected_by_reason: [AtomicU64; REJECT_REASONS],
    /// Stamp (ns) of the newest accepted PartStates; 0 = none yet.
    pub parts_stamp_ns: AtomicU64,
    /// Stamp (ns) of the newest accepted request (or explicit schedule).
    pub request_stamp_ns: AtomicU64,
    /// Deadline (ns) of the newest accepted request; u64::MAX = none.
    pub request_deadline_ns: AtomicU64,
    /// Driver faults seen by the motor thread.
    pub driver_faults: AtomicU64,
    /// Command entries the driver clamped (its own running count).
    pub driver_clamped: AtomicU64,
    /// Commands the driver rejected (its own running count).
    pub driver_rejected: AtomicU64,
    /// Transitions into hold because of a driver fault.
    pub fault_holds: AtomicU64,
    /// Fault holds left again.
    pub resumes: AtomicU64,
    /// Set by a valid resume command, taken by the motor.
    pub resume_requested: AtomicBool,
    /// Set by an operator's stop, cleared by a start: the motor idles at
    /// the next cycle boundary, where the plate is home.
    pub operator_stop: AtomicBool,
    /// Rung by the receiver when it hands the solver messages (and by the
    /// io thread to stop); the solver thread sleeps on it.
    pub solver_doorbell: super::doorbell::Doorbell,
    pose: [AtomicU64; 3],
    /// The feed-forward's plate mass and inertia over the model's (f64
    /// bits), and the cycles that updated or were skipped (motor → reports).
    inertia_scale: [AtomicU64; 2],
    inertia_updates: AtomicU64,
    inertia_skipped: AtomicU64,
    /// Set by the io thread to stop: the motor finishes its cycle, brings
    /// the plate home and exits.
    pub stop: AtomicBool,
    /// Set by the motor thread once the plate is home after `stop`.
    pub motor_done: AtomicBool,
    /// RT-thread allocation count when this core started (the counter is
    /// process-wide; telemetry reports allocations since start).
    pub allocation_baseline: AtomicU64,
    /// A thread of the core stopped (permanent; see [`Self::record_thread_death`]).
    thread_fault: Health,
    /// The driver reported a fault and the motor holds (cleared on resume).
    driver_fault: AtomicU32,
    /// The driver's bus state, faults and lost frames (motor → telemetry).
    pub driver: super::driver_cell::DriverCell,
}

/// The first death of a core thread: written once, then published by a
/// release store of `source`.
#[derive(Debug)]
struct Health {
    claimed: AtomicBool,
    source: AtomicU32,
    cause: AtomicU32,
    detail: [AtomicU8; HEALTH_DETAIL_BYTES],
}

impl Default for Health {
    fn default() -> Self {
        Self {
            claimed: AtomicBool::new(false),
            source: AtomicU32::new(0),
            cause: AtomicU32::new(0),
            detail: [const { AtomicU8::new(0) }; HEALTH_DETAIL_BYTES],
        }
    }
}

/// The plate's mass and inertia over the model's, as the motor's
/// feed-forward has them ([`upm_motion::InertiaEstimate`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InertiaReport {
    pub scale: [f64; 2],
    /// Cycles that updated the scales, and cycles skipped.
    pub updates: u64,
    pub skipped: u64,
}

/// What [`CoreShared::health`] reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HealthReport {
    pub source: HealthSource,
    pub cause: HealthCause,
    pub detail: [u8; HEALTH_DETAIL_BYTES],
}

impl HealthReport {
    pub const OK: Self =
        Self { source: HealthSource::Ok, cause: HealthCause::None, detail: [0; HEALTH_DETAIL_BYTES] };

    pub fn detail_str(&self) -> &str {
        ipc_types::detail_str(&self.detail)
    }
}

impl CoreShared {
    pub fn new() -> Self {
        let s = Self::default();
        s.request_deadline_ns.store(u64::MAX, Relaxed);
        s.set_inertia([1.0; 2], 0, 0);
        s.allocation_baseline.store(super::alloc_count::rt_allocations(), Relaxed);
        s
    }

    pub fn state(&self) -> CoreState {
        CoreState::from_code(self.state.load(Relaxed)).unwrap_or(CoreState::Fault)
    }

    pub fn set_state(&self, s: CoreState) {
        self.state.store(s.code(), Relaxed);
    }

    pub fn set_pose(&self, p: &Pose) {
        self.pose[0].store(p.x.to_bits(), Relaxed);
        self.pose[1].store(p.y.to_bits(), Relaxed);
        self.pose[2].store(p.theta.to_bits(), Relaxed);
    }

    pub fn pose(&self) -> [f64; 3] {
        [0, 1, 2].map(|i| f64::from_bits(self.pose[i].load(Relaxed)))
    }

    pub fn set_inertia(&self, scale: [f64; 2], updates: u64, skipped: u64) {
        for (a, s) in self.inertia_scale.iter().zip(scale) {
            a.store(s.to_bits(), Relaxed);
        }
        self.inertia_updates.store(updates, Relaxed);
        self.inertia_skipped.store(skipped, Relaxed);
    }

    /// What the motor's feed-forward takes the plate to be.
    pub fn inertia(&self) -> InertiaReport {
        InertiaReport {
            scale: [0, 1].map(|i| f64::from_bits(self.inertia_scale[i].load(Relaxed))),
            updates: self.inertia_updates.load(Relaxed),
            skipped: self.inertia_skipped.load(Relaxed),
        }
    }

    /// Count one rejected message under `reason`.
    pub fn count_reject(&self, reason: RejectReason) {
        self.rejected_by_reason[reason.index()].fetch_add(1, Relaxed);
    }

    /// Count `n` rejected messages under `reason`.
    pub fn count_rejects(&self, reason: RejectReason, n: u64) {
        if n > 0 {
            self.rejected_by_reason[reason.index()].fetch_add(n, Relaxed);
        }
    }

    /// Rejections per [`RejectReason`] code.
    pub fn rejected_by_reason(&self) -> [u64; REJECT_REASONS] {
        core::array::from_fn(|i| self.rejected_by_reason[i].load(Relaxed))
    }

    /// Counters as published in telemetry; `rt_thread_allocations` is
    /// filled in by the caller from the allocation counter.
    pub fn counters(&self) -> CoreCounters {
        CoreCounters {
            ticks: self.ticks.load(Relaxed),
            overruns: self.overruns.load(Relaxed),
            hold_events: self.hold_events.load(Relaxed),
            schedule_swaps: self.schedule_swaps.load(Relaxed),
            rejected_parts: self.rejected_parts.load(Relaxed),
            rejected_requests: self.rejected_requests.load(Relaxed),
            rt_thread_allocations: 0,
            driver_faults: self.driver_faults.load(Relaxed),
            driver_clamped: self.driver_clamped.load(Relaxed),
            driver_rejected: self.driver_rejected.load(Relaxed),
            fault_holds: self.fault_holds.load(Relaxed),
            resumes: self.resumes.load(Relaxed),
        }
    }

    /// True if the newest input is too old at `now_ns` (or there is none).
    pub fn inputs_stale(&self, now_ns: u64, parts_max_age_ns: u64, request_max_age_ns: u64) -> bool {
        let parts = self.parts_stamp_ns.load(Relaxed);
        let request = self.request_stamp_ns.load(Relaxed);
        let deadline = self.request_deadline_ns.load(Relaxed);
        parts == 0
            || request == 0
            || now_ns.saturating_sub(parts) > parts_max_age_ns
            || now_ns.saturating_sub(request) > request_max_age_ns
            || now_ns > deadline
    }

    /// Record that a core thread stopped. Only the first death is kept.
    /// Allocation-free and lock-free: it runs inside a panic hook on an RT
    /// thread.
    pub fn record_thread_death(
        &self,
        source: HealthSource,
        cause: HealthCause,
        detail: core::fmt::Arguments<'_>,
    ) {
        if self.thread_fault.claimed.swap(true, Relaxed) {
            return;
        }
        let mut text = DetailText::new();
        let _ = text.write_fmt(detail);
        for (dst, &b) in self.thread_fault.detail.iter().zip(&text.bytes) {
            dst.store(b, Relaxed);
        }
        self.thread_fault.cause.store(cause as u32, Relaxed);
        self.thread_fault.source.store(source as u32, Release);
    }

    /// True once a core thread has stopped unexpectedly.
    pub fn thread_died(&self) -> bool {
        self.thread_fault.source.load(Acquire) != HealthSource::Ok as u32
    }

    /// The motor holds because the driver reported `cause`.
    pub fn set_driver_fault(&self, cause: Option<HealthCause>) {
        self.driver_fault.store(cause.map_or(0, |c| c as u32), Relaxed);
    }

    /// Health as telemetry shows it: a dead thread first, else a driver
    /// fault hold, else ok.
    pub fn health(&self) -> HealthReport {
        let source = self.thread_fault.source.load(Acquire);
        if let Some(source) = HealthSource::from_code(source).filter(|&s| s != HealthSource::Ok) {
            let cause =
                HealthCause::from_code(self.thread_fault.cause.load(Relaxed)).unwrap_or(HealthCause::None);
            let detail = core::array::from_fn(|i| self.thread_fault.detail[i].load(Relaxed));
            return HealthReport { source, cause, detail };
        }
        match HealthCause::from_code(self.driver_fault.load(Relaxed)) {
            Some(HealthCause::None) | None => HealthReport::OK,
            Some(cause) => {
                HealthReport { source: HealthSource::Driver, cause, detail: [0; HEALTH_DETAIL_BYTES] }
            }
        }
    }
}
