//! Tunables of the EtherCAT driver, with defaults.

use core::fmt;

use serde::{Deserialize, Serialize};
use upm_hardware::MAX_ACTUATORS;

/// A SubDevice the rig expects at a position on the bus: its identity
/// from the drive's SII (`[[driver.subdevices]]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ExpectedSubDevice {
    pub vendor: u32,
    pub product: u32,
}

impl ExpectedSubDevice {
    /// The simulated chain's CiA 402 drive.
    pub const SIMULATED_DRIVE: Self = Self { vendor: 0x0055_504D, product: 0x0000_0402 };
}

/// What `[driver]` of the rig file sets is read straight into these; the
/// drives expected, their count and the motor's rate are the caller's.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct EthercatParams {
    /// One drive per actuator, in bus order (only `count` are used).
    #[serde(skip)]
    pub expected: [ExpectedSubDevice; MAX_ACTUATORS],
    #[serde(skip)]
    pub count: usize,
    /// The motor loop's rate (Hz).
    #[serde(skip)]
    pub tick_hz: f64,
    /// One process-data exchange every `cycle_divisor` motor ticks; the
    /// bus cycle must be 1–4 kHz.
    pub cycle_divisor: u32,
    /// Position resolution of the drives (counts per metre of stroke).
    pub counts_per_metre: f64,
    /// Following-error window written to 0x6065 (m).
    pub following_error_m: f64,
    /// Force that 1000 ‰ of the drive's torque means (N): feed-forward
    /// (0x60B2) and actual torque (0x6077) are scaled by it.
    pub rated_force_n: f64,
    /// Per-frame deadline at start-up (ms), for ethercrab's PDU timeout.
    #[serde(skip)]
    pub startup_pdu_timeout_ms: u64,
    /// Exchanges allowed for every drive to reach operation enabled.
    #[serde(skip)]
    pub enable_cycles: u32,
    /// Run the drives on distributed-clock SYNC0 at the bus cycle when
    /// every one of them offers it (otherwise, or when false, free run:
    /// each drive acts when the frame passes).
    pub distributed_clocks: bool,
}

impl Default for EthercatParams {
    fn default() -> Self {
        Self {
            expected: [ExpectedSubDevice::SIMULATED_DRIVE; MAX_ACTUATORS],
            count: 4,
            tick_hz: 10_000.0,
            cycle_divisor: 3,
            counts_per_metre: 1e8,
            following_error_m: 2e-3,
            rated_force_n: 2e4,
            startup_pdu_timeout_ms: 100,
            enable_cycles: 100,
            distributed_clocks: true,
        }
    }
}

/// A parameter out of range, by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamsError {
    Count,
    CycleRate,
    CountsPerMetre,
    FollowingError,
    RatedForce,
    EnableCycles,
}

impl fmt::Display for ParamsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Count => "driver: expected subdevices must number 3..=8, one per actuator",
            Self::CycleRate => "driver.cycle_divisor: the bus cycle (tick rate / divisor) must be 1–4 kHz",
            Self::CountsPerMetre => "driver.counts_per_metre must be finite and > 0",
            Self::FollowingError => "driver.following_error_m must be finite and > 0",
            Self::RatedForce => "driver.rated_force_n must be finite and > 0",
            Self::EnableCycles => "driver.enable_cycles must be > 0",
        })
    }
}

impl core::error::Error for ParamsError {}

impl EthercatParams {
    /// The bus cycle (Hz).
    pub fn cycle_hz(&self) -> f64 {
        self.tick_hz / f64::from(self.cycle_divisor.max(1))
    }

    /// How long a wire waits for a frame's answer: half a bus cycle.
    pub fn frame_deadline(&self) -> core::time::Duration {
        core::time::Duration::from_secs_f64(0.5 / self.cycle_hz())
    }

    pub fn validate(&self) -> Result<(), ParamsError> {
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(3..=MAX_ACTUATORS).contains(&self.count) {
            return Err(ParamsError::Count);
        }
        let hz = self.cycle_hz();
        if self.cycle_divisor == 0 || !positive(self.tick_hz) || !(999.0..=4001.0).contains(&hz) {
            return Err(ParamsError::CycleRate);
        }
        if !positive(self.counts_per_metre) {
            return Err(ParamsError::CountsPerMetre);
        }
        if !positive(self.following_error_m)
            || self.following_error_m * self.counts_per_metre >= u32::MAX as f64
        {
            return Err(ParamsError::FollowingError);
        }
        if !positive(self.rated_force_n) {
            return Err(ParamsError::RatedForce);
        }
        if self.enable_cycles == 0 {
            return Err(ParamsError::EnableCycles);
        }
        Ok(())
    }
}
