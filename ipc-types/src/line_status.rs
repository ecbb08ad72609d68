//! LineStatus: line process → all, a few times a second: what the line
//! interface (its OPC UA and Modbus TCP servers) refused, by kind, and
//! what it passed on to the rig, so `upm status` can show it.

use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::PROTOCOL_VERSION;
use crate::header::{HeaderError, OldStamps, check_header};
use crate::validation::ValidationLimits;

/// Line process → all: the line interface's connections and counters.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::LineStatus.v6"))]
pub struct LineStatus {
    pub protocol_version: u32,
    /// The line process's pid.
    pub line_pid: u32,
    /// Status number: one more for each status the line publishes.
    pub seq: u64,
    /// CLOCK_MONOTONIC ns when it was written.
    pub stamp_ns: u64,
    /// OPC UA sessions open now.
    pub opcua_sessions: u32,
    /// Modbus TCP connections open now.
    pub modbus_connections: u32,
    // Since the line started, by kind of refusal:
    /// OPC UA logins with an unknown user or a wrong password.
    pub login_failures: u64,
    /// OPC UA method calls or writes refused for want of a user.
    pub access_denied: u64,
    /// OPC UA calls with arguments of the wrong type or number.
    pub bad_arguments: u64,
    /// `Picked` on a pose with no part ready.
    pub invalid_state: u64,
    /// OPC UA calls the rig could not carry out.
    pub failed_calls: u64,
    /// Modbus requests answered with an exception.
    pub modbus_exceptions: u64,
    /// Modbus connections closed on a malformed frame.
    pub modbus_bad_frames: u64,
    /// Modbus connections refused beyond the limit.
    pub modbus_refused_connections: u64,
    /// Picks the line passed on to the rig (`PickCommand`s sent).
    pub picks_sent: u64,
    /// Recipes the line loaded (`RecipeCommand`s sent).
    pub recipes_loaded: u64,
    /// Recipe loads the line refused.
    pub recipes_refused: u64,
}

const _: () = assert!(size_of::<LineStatus>() == 4 + 4 + 8 + 8 + 4 + 4 + 11 * 8);

/// Why a [`LineStatus`] is not a usable report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineStatusError {
    /// Protocol version or stamp.
    Header(HeaderError),
}

impl fmt::Display for LineStatusError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("line_status", f),
        }
    }
}

impl core::error::Error for LineStatusError {}

impl Default for LineStatus {
    fn default() -> Self {
        Self::new()
    }
}

impl LineStatus {
    /// The protocol version set, every other field 0.
    pub const fn new() -> Self {
        Self {
            protocol_version: PROTOCOL_VERSION,
            line_pid: 0,
            seq: 0,
            stamp_ns: 0,
            opcua_sessions: 0,
            modbus_connections: 0,
            login_failures: 0,
            access_denied: 0,
            bad_arguments: 0,
            invalid_state: 0,
            failed_calls: 0,
            modbus_exceptions: 0,
            modbus_bad_frames: 0,
            modbus_refused_connections: 0,
            picks_sent: 0,
            recipes_loaded: 0,
            recipes_refused: 0,
        }
    }

    /// Check the header: version, and a stamp not in the future (of any
    /// age: a late reader still wants the newest). Allocation-free; every
    /// counter value is valid.
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), LineStatusError> {
        check_header(self.protocol_version, None, self.stamp_ns, OldStamps::Accept, limits)
            .map_err(LineStatusError::Header)
    }

    /// The refusal counters by name (the field's), in field order.
    pub const fn refusals(&self) -> [(&'static str, u64); 8] {
        [
            ("login_failures", self.login_failures),
            ("access_denied", self.access_denied),
            ("bad_arguments", self.bad_arguments),
            ("invalid_state", self.invalid_state),
            ("failed_calls", self.failed_calls),
            ("modbus_exceptions", self.modbus_exceptions),
            ("modbus_bad_frames", self.modbus_bad_frames),
            ("modbus_refused_connections", self.modbus_refused_connections),
        ]
    }

    /// Every refusal since the line started (saturating: a hostile
    /// status cannot overflow it).
    pub fn total_refusals(&self) -> u64 {
        self.refusals().iter().fold(0u64, |sum, (_, n)| sum.saturating_add(*n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_new_status_is_valid_and_counts_nothing() {
        let limits = ValidationLimits::new([1.0, 1.0], 1_000);
        let m = LineStatus::new();
        assert_eq!((m.protocol_version, m.total_refusals()), (PROTOCOL_VERSION, 0));
        assert_eq!(m.validate(&limits), Ok(()), "a zero stamp is of any age");
        let mut late = m;
        late.stamp_ns = 1_000 + limits.max_future_skew_ns + 1;
        assert!(matches!(
            late.validate(&limits),
            Err(LineStatusError::Header(HeaderError::StampFromFuture { .. }))
        ));
        let mut old = m;
        old.protocol_version = 5;
        assert_eq!(
            old.validate(&limits).map_err(|e| e.to_string()),
            Err("line_status.protocol_version is 5, expected 6".to_owned())
        );
    }

    #[test]
    fn refusals_name_each_counter_and_add_up() {
        let mut m = LineStatus::new();
        (m.login_failures, m.access_denied, m.bad_arguments, m.invalid_state) = (1, 2, 3, 4);
        (m.failed_calls, m.modbus_exceptions, m.modbus_bad_frames, m.modbus_refused_connections) =
            (5, 6, 7, 8);
        (m.picks_sent, m.recipes_loaded, m.recipes_refused) = (100, 200, 300);
        let r = m.refusals();
        assert_eq!(r[0], ("login_failures", 1));
        assert_eq!(r[7], ("modbus_refused_connections", 8));
        assert_eq!(r.iter().map(|(_, n)| *n).collect::<Vec<u64>>(), [1, 2, 3, 4, 5, 6, 7, 8]);
        assert_eq!(m.total_refusals(), 36, "picks and recipes are no refusals");
        m.failed_calls = u64::MAX;
        assert_eq!(m.total_refusals(), u64::MAX);
    }
}
