//! `[rt]`, `[safety]` and `[telemetry]`: how the core runs.

use rt_core::{CoreParams, RtParams};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct RtSection {
    pub motor_priority: u8,
    pub solver_priority: u8,
    /// CPU to pin the motor thread to; -1 = not pinned.
    pub motor_cpu: i64,
    pub solver_cpu: i64,
    pub lock_memory: bool,
    pub solver_poll_us: u64,
    /// How the core's receiver thread waits for clients.
    pub receiver: Receiver,
    /// SCHED_FIFO priority of the receiver in event mode; 0 = normal.
    pub receiver_priority: u8,
    /// PM QoS request held on /dev/cpu_dma_latency (µs), or "leave".
    pub cpu_dma_latency_us: DmaLatency,
    /// Keep normal-priority work (the core's io thread, the clients `upm
    /// run` starts) off the motor's CPU.
    pub isolate_motor_cpu: bool,
}

/// `rt.cpu_dma_latency_us`: a bound in µs, or `"leave"` the host's policy.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, Eq)]
#[serde(untagged)]
pub enum DmaLatency {
    Us(u32),
    Keyword(String),
}

/// `rt.receiver`: sleep on the clients' wake-up event, or busy-poll.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum Receiver {
    #[default]
    Event,
    Spin,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SafetySection {
    pub parts_max_age_ms: f64,
    pub request_max_age_ms: f64,
    pub max_future_skew_ms: f64,
    /// A driver-fault hold ends by itself after this many ms of healthy
    /// driver reads; 0 = only `upm resume` ends it.
    pub auto_resume_ms: f64,
    /// After a core thread dies, how long the core reports it (plate held)
    /// before it exits with an error.
    pub fault_exit_ms: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct TelemetrySection {
    pub period_ms: f64,
    /// Where upm-core writes `*.hgrm` at exit ("" = not written).
    pub histogram_dir: String,
}

impl Default for RtSection {
    fn default() -> Self {
        let r = RtParams::default();
        let cpu = |c: Option<usize>| c.map_or(-1, |c| c as i64);
        Self {
            motor_priority: r.motor_priority,
            solver_priority: r.solver_priority,
            motor_cpu: cpu(r.motor_cpu),
            solver_cpu: cpu(r.solver_cpu),
            lock_memory: r.lock_memory,
            solver_poll_us: CoreParams::default().solver_poll_ns / 1000,
            receiver: Receiver::Event,
            receiver_priority: r.receiver_priority,
            cpu_dma_latency_us: r
                .cpu_dma_latency_us
                .map_or(DmaLatency::Keyword("leave".into()), DmaLatency::Us),
            isolate_motor_cpu: r.isolate_motor_cpu,
        }
    }
}

impl Default for SafetySection {
    fn default() -> Self {
        let c = CoreParams::default();
        Self {
            parts_max_age_ms: c.parts_max_age_ns as f64 / 1e6,
            request_max_age_ms: c.request_max_age_ns as f64 / 1e6,
            max_future_skew_ms: c.max_future_skew_ns as f64 / 1e6,
            auto_resume_ms: c.auto_resume_ns as f64 / 1e6,
            fault_exit_ms: c.fault_exit_ns as f64 / 1e6,
        }
    }
}

impl Default for TelemetrySection {
    fn default() -> Self {
        Self {
            period_ms: CoreParams::default().telemetry_period_ns as f64 / 1e6,
            histogram_dir: String::new(),
        }
    }
}

impl RtSection {
    /// The RT parameters; the message names the field.
    pub fn params(&self) -> Result<RtParams, String> {
        if self.solver_poll_us == 0 {
            return Err("rt.solver_poll_us must be positive".into());
        }
        Ok(RtParams {
            motor_priority: self.motor_priority,
            solver_priority: self.solver_priority,
            motor_cpu: cpu(self.motor_cpu, "rt.motor_cpu")?,
            solver_cpu: cpu(self.solver_cpu, "rt.solver_cpu")?,
            lock_memory: self.lock_memory,
            receiver: match self.receiver {
                Receiver::Event => rt_core::ReceiverWake::Event,
                Receiver::Spin => rt_core::ReceiverWake::Spin,
            },
            receiver_priority: self.receiver_priority,
            isolate_motor_cpu: self.isolate_motor_cpu,
            cpu_dma_latency_us: match &self.cpu_dma_latency_us {
                DmaLatency::Us(us) => Some(*us),
                DmaLatency::Keyword(k) if k == "leave" => None,
                DmaLatency::Keyword(k) => {
                    return Err(format!(
                        "rt.cpu_dma_latency_us must be a number of µs or \"leave\", got {k:?}"
                    ));
                }
            },
        })
    }

    /// The motor thread's CPU, if it is pinned (and the number is valid).
    pub fn motor_cpu(&self) -> Option<usize> {
        cpu(self.motor_cpu, "rt.motor_cpu").ok().flatten()
    }
}

/// Milliseconds (finite, > 0) to nanoseconds, or a message naming `field`.
pub(super) fn ms_to_ns(ms: f64, field: &str) -> Result<u64, String> {
    if ms.is_finite() && ms > 0.0 && ms < 1e9 {
        Ok((ms * 1e6).round() as u64)
    } else {
        Err(format!("{field} must be a positive number of milliseconds, got {ms}"))
    }
}

/// Like [`ms_to_ns`], but 0 is allowed (it turns the feature off).
pub(super) fn ms_to_ns_or_zero(ms: f64, field: &str) -> Result<u64, String> {
    if ms == 0.0 {
        return Ok(0);
    }
    ms_to_ns(ms, field)
        .map_err(|_| format!("{field} must be 0 or a positive number of milliseconds, got {ms}"))
}

/// A CPU to pin to: one this process may run on (its affinity mask), or -1.
fn cpu(c: i64, field: &str) -> Result<Option<usize>, String> {
    let allowed = rt_core::rt_setup::allowed_cpus();
    match c {
        -1 => Ok(None),
        c if c >= 0 && allowed.contains(&(c as usize)) => Ok(Some(c as usize)),
        c => Err(format!("{field} = {c}: this process may run on CPUs {allowed:?} (or -1 for no pinning)")),
    }
}
