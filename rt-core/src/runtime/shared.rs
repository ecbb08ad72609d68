//! State the threads share through atomics only (no locks): counters,
//! the operating state, the stamps staleness is judged on, and the
//! commanded plate pose. Values are individually consistent, not a snapshot.

use core::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering::Relaxed};

use ipc_types::{CoreCounters, CoreState};

use crate::motion::Pose;

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
    /// Stamp (ns) of the newest accepted PartStates; 0 = none yet.
    pub parts_stamp_ns: AtomicU64,
    /// Stamp (ns) of the newest accepted request (or explicit schedule).
    pub request_stamp_ns: AtomicU64,
    /// Deadline (ns) of the newest accepted request; u64::MAX = none.
    pub request_deadline_ns: AtomicU64,
    /// Driver faults seen by the motor thread.
    pub driver_faults: AtomicU64,
    /// Commands the driver refused or clamped (from its own counters).
    pub driver_clamped: AtomicU64,
    pose: [AtomicU64; 3],
    /// Set by the io thread to stop: the motor finishes its cycle, brings
    /// the plate home and exits.
    pub stop: AtomicBool,
    /// Set by the motor thread once the plate is home after `stop`.
    pub motor_done: AtomicBool,
    /// RT-thread allocation count when this core started (the counter is
    /// process-wide; telemetry reports allocations since start).
    pub allocation_baseline: AtomicU64,
}

impl CoreShared {
    pub fn new() -> Self {
        let s = Self::default();
        s.request_deadline_ns.store(u64::MAX, Relaxed);
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
}
