//! Test-only faults (cargo feature `fault-injection`, off in every build
//! but the test suite's): make a core thread panic, or the driver report
//! faults, at a chosen time after start. Read once from the environment
//! at start-up:
//!
//! `UPM_INJECT_FAULT=motor_thread:300` (ms after start), or
//! `UPM_INJECT_FAULT=driver:300:200` (read faults from 300 ms for 200 ms).

use ipc_types::{HealthSource, monotonic_now_ns};

use upm_hardware::ReadError;

/// What to inject and when (monotonic ns; `u64::MAX` = never).
#[derive(Debug, Clone, Copy)]
pub struct FaultPlan {
    panic_thread: HealthSource,
    panic_at_ns: u64,
    driver_from_ns: u64,
    driver_until_ns: u64,
}

impl FaultPlan {
    pub const NONE: Self = Self {
        panic_thread: HealthSource::Ok,
        panic_at_ns: u64::MAX,
        driver_from_ns: u64::MAX,
        driver_until_ns: 0,
    };

    /// The plan in `UPM_INJECT_FAULT`, relative to now; none if unset or
    /// malformed.
    pub fn from_env() -> Self {
        let Ok(spec) = std::env::var("UPM_INJECT_FAULT") else { return Self::NONE };
        let now = monotonic_now_ns();
        let mut it = spec.split(':');
        let what = it.next().unwrap_or("");
        let mut ms = it.map(|v| v.parse::<u64>().ok().map(|ms| ms.saturating_mul(1_000_000)));
        let at = ms.next().flatten().map_or(u64::MAX, |d| now.saturating_add(d));
        let thread = match what {
            "motor_thread" => HealthSource::MotorThread,
            "solver_thread" => HealthSource::SolverThread,
            "receiver_thread" => HealthSource::ReceiverThread,
            "driver" => {
                let until = ms.next().flatten().map_or(0, |d| at.saturating_add(d));
                return Self { driver_from_ns: at, driver_until_ns: until, ..Self::NONE };
            }
            _ => return Self::NONE,
        };
        Self { panic_thread: thread, panic_at_ns: at, ..Self::NONE }
    }

    /// Panic (with a literal message) if `thread` is due.
    pub fn panic_if_due(&self, thread: HealthSource, now_ns: u64) {
        if thread == self.panic_thread && now_ns >= self.panic_at_ns {
            panic!("injected fault");
        }
    }

    /// The driver's read, turned into a fault inside the planned window.
    pub fn driver_read(&self, read: Result<(), ReadError>, now_ns: u64) -> Result<(), ReadError> {
        if (self.driver_from_ns..self.driver_until_ns).contains(&now_ns) {
            Err(ReadError::Fault)
        } else {
            read
        }
    }
}
