//! `[safety]` and `[telemetry]` of the rig file: when the core holds the
//! plate, and how often it reports.

use core::fmt;

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SafetyParams {
    /// PartStates older than this (by their stamp) put the core in hold.
    #[serde(rename = "parts_max_age_ms", with = "upm_units::ms_as_ns")]
    pub parts_max_age_ns: u64,
    /// Requests older than this (or past their own deadline) put the core in hold.
    #[serde(rename = "request_max_age_ms", with = "upm_units::ms_as_ns")]
    pub request_max_age_ns: u64,
    /// How far a message stamp may be ahead of the core's clock.
    #[serde(rename = "max_future_skew_ms", with = "upm_units::ms_as_ns")]
    pub max_future_skew_ns: u64,
    /// A driver-fault hold ends by itself after this long of healthy driver
    /// reads; 0 = only `upm resume` ends it.
    #[serde(rename = "auto_resume_ms", with = "upm_units::ms_as_ns")]
    pub auto_resume_ns: u64,
    /// After a core thread dies, how long the core keeps publishing its
    /// health (plate held) before it exits with an error.
    #[serde(rename = "fault_exit_ms", with = "upm_units::ms_as_ns")]
    pub fault_exit_ns: u64,
}

impl Default for SafetyParams {
    fn default() -> Self {
        Self {
            parts_max_age_ns: 200_000_000,
            request_max_age_ns: 200_000_000,
            max_future_skew_ns: 1_000_000,
            auto_resume_ns: 0,
            fault_exit_ns: 2_000_000_000,
        }
    }
}

/// Which `[safety]` bound is zero where it must not be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SafetyError {
    PartsMaxAge,
    RequestMaxAge,
    MaxFutureSkew,
}

impl fmt::Display for SafetyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let field = match self {
            Self::PartsMaxAge => "parts_max_age_ms",
            Self::RequestMaxAge => "request_max_age_ms",
            Self::MaxFutureSkew => "max_future_skew_ms",
        };
        write!(f, "safety.{field} must be a positive number of milliseconds")
    }
}

impl core::error::Error for SafetyError {}

impl SafetyParams {
    /// The ages and the skew must be positive; `auto_resume` and
    /// `fault_exit` may be 0 (off).
    pub fn validate(&self) -> Result<(), SafetyError> {
        if self.parts_max_age_ns == 0 {
            return Err(SafetyError::PartsMaxAge);
        }
        if self.request_max_age_ns == 0 {
            return Err(SafetyError::RequestMaxAge);
        }
        if self.max_future_skew_ns == 0 {
            return Err(SafetyError::MaxFutureSkew);
        }
        Ok(())
    }
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct TelemetryParams {
    /// Telemetry publish period (io thread), at least 1 ms.
    #[serde(rename = "period_ms", with = "upm_units::ms_as_ns")]
    pub period_ns: u64,
    /// Where upm-core writes `*.hgrm` at exit ("" = not written).
    pub histogram_dir: String,
}

impl Default for TelemetryParams {
    fn default() -> Self {
        Self { period_ns: 50_000_000, histogram_dir: String::new() }
    }
}
