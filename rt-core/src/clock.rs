//! The time source of the loops, injected so that lock-step tests can step
//! it by hand (copper-rs style) while the real process sleeps on
//! CLOCK_MONOTONIC.

use core::sync::atomic::{AtomicU64, Ordering};

/// A monotonic nanosecond clock the motor and solver loops sleep on.
pub trait Clock: Send + Sync {
    /// Now, in CLOCK_MONOTONIC nanoseconds (or manual time).
    fn now_ns(&self) -> u64;
    /// Sleep until the absolute time `deadline_ns` (returns at once if it
    /// has passed).
    fn sleep_until(&self, deadline_ns: u64);
}

/// CLOCK_MONOTONIC with absolute-deadline `clock_nanosleep`: the only
/// syscall the RT threads make.
#[derive(Debug, Clone, Copy, Default)]
pub struct MonotonicClock;

impl Clock for MonotonicClock {
    #[inline]
    fn now_ns(&self) -> u64 {
        ipc_types::monotonic_now_ns()
    }

    fn sleep_until(&self, deadline_ns: u64) {
        let ts = libc::timespec {
            tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
            tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
        };
        loop {
            // SAFETY: `ts` is a valid timespec; a null remainder is allowed
            // with TIMER_ABSTIME.
            let rc = unsafe {
                libc::clock_nanosleep(libc::CLOCK_MONOTONIC, libc::TIMER_ABSTIME, &ts, core::ptr::null_mut())
            };
            // Absolute deadlines make a restart after a signal exact.
            if rc != libc::EINTR {
                return;
            }
        }
    }
}

/// Manual time for lock-step runs: `sleep_until` jumps the clock forward, so
/// a run takes no wall-clock time and is bit-identical every time.
#[derive(Debug, Default)]
pub struct ManualClock {
    now: AtomicU64,
}

impl ManualClock {
    pub fn new(start_ns: u64) -> Self {
        Self { now: AtomicU64::new(start_ns) }
    }

    /// Move time forward by `ns`.
    pub fn advance(&self, ns: u64) {
        self.now.fetch_add(ns, Ordering::Relaxed);
    }
}

impl Clock for ManualClock {
    fn now_ns(&self) -> u64 {
        self.now.load(Ordering::Relaxed)
    }

    fn sleep_until(&self, deadline_ns: u64) {
        self.now.fetch_max(deadline_ns, Ordering::Relaxed);
    }
}
