//! `[rt]` of the rig file: where and how the core's threads run.

use serde::{Deserialize, Serialize};

/// Real-time placement of the threads.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct RtParams {
    /// SCHED_FIFO priority of the motor thread (1–99).
    pub motor_priority: u8,
    /// SCHED_FIFO priority of the solver thread (1–99, below the motor's).
    pub solver_priority: u8,
    /// CPU the motor thread is pinned to (`None`, -1 in the file: not pinned).
    #[serde(with = "upm_units::cpu")]
    pub motor_cpu: Option<usize>,
    /// CPU the solver thread is pinned to.
    #[serde(with = "upm_units::cpu")]
    pub solver_cpu: Option<usize>,
    /// `mlockall` and prefault at start-up.
    pub lock_memory: bool,
    /// Solver thread poll period.
    #[serde(rename = "solver_poll_us", with = "upm_units::us_as_ns")]
    pub solver_poll_ns: u64,
    /// How the receiver thread waits for client messages.
    pub receiver: ReceiverWake,
    /// SCHED_FIFO priority of the receiver thread in `Event` mode (0 = normal
    /// scheduling; else 1–99, below the motor's). It then runs pinned to the
    /// motor's CPU: the motor preempts it, and it preempts neither the motor
    /// nor, on the other CPU, the solver. Not applied in `Spin` mode, where a
    /// real-time busy loop would starve its CPU.
    pub receiver_priority: u8,
    /// PM QoS request held on /dev/cpu_dma_latency for the core's life (µs
    /// an idle CPU may take to wake); `None` ("leave" in the file) leaves
    /// the host's idle policy.
    #[serde(with = "dma_latency")]
    pub cpu_dma_latency_us: Option<u32>,
    /// Keep normal-priority work (the core's io thread, the clients `upm
    /// run` starts) off the motor's CPU: only the motor and the receiver,
    /// which the motor preempts, run there.
    pub isolate_motor_cpu: bool,
}

/// How the receiver thread learns of a client message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
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
            solver_poll_ns: 500_000,
            receiver: ReceiverWake::Event,
            receiver_priority: 75,
            cpu_dma_latency_us: Some(0),
            isolate_motor_cpu: true,
        }
    }
}

/// `rt.cpu_dma_latency_us`: a bound in µs, or `"leave"` the host's policy.
mod dma_latency {
    use serde::de::Error;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Deserialize, Serialize)]
    #[serde(untagged)]
    enum Written {
        Us(u32),
        Keyword(String),
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u32>, D::Error> {
        match Written::deserialize(d)? {
            Written::Us(us) => Ok(Some(us)),
            Written::Keyword(k) if k == "leave" => Ok(None),
            Written::Keyword(k) => {
                Err(D::Error::custom(format!("a number of µs or \"leave\" is needed, got {k:?}")))
            }
        }
    }

    pub fn serialize<S: Serializer>(us: &Option<u32>, s: S) -> Result<S::Ok, S::Error> {
        match us {
            Some(us) => Written::Us(*us),
            None => Written::Keyword("leave".into()),
        }
        .serialize(s)
    }
}
