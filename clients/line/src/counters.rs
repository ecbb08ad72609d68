//! What the line refused, by kind, and what it passed on: shown as
//! `Rig.Line.*` over OPC UA, published as `LineStatus` for `upm status`,
//! and printed when the line stops.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use ipc_types::LineStatus;
use upm_rig_client::client_counters::ClientCounters;

#[derive(Debug, Default)]
pub struct LineCounters {
    /// OPC UA logins with an unknown user or a wrong password.
    pub login_failures: AtomicU64,
    /// OPC UA method calls or writes refused for want of a user.
    pub access_denied: AtomicU64,
    /// OPC UA calls with arguments of the wrong type or number.
    pub bad_arguments: AtomicU64,
    /// `Picked` on a pose with no part ready (or on a rig whose own robot
    /// picks).
    pub invalid_state: AtomicU64,
    /// OPC UA calls the rig could not carry out (its view thread gone).
    pub failed_calls: AtomicU64,
    /// Modbus requests answered with an exception.
    pub modbus_exceptions: AtomicU64,
    /// Modbus connections closed on a malformed frame.
    pub modbus_bad_frames: AtomicU64,
    /// Modbus connections refused beyond the limit.
    pub modbus_refused_connections: AtomicU64,
    /// Picks passed on to the rig; recipes loaded, and refused.
    pub picks_sent: AtomicU64,
    pub recipes_loaded: AtomicU64,
    pub recipes_refused: AtomicU64,
    /// Open now: OPC UA sessions, Modbus connections.
    pub opcua_sessions: AtomicU64,
    pub modbus_connections: AtomicU64,
}

impl LineCounters {
    pub fn count(counter: &AtomicU64) {
        counter.fetch_add(1, Relaxed);
    }

    /// (name, value) of each counter, for display.
    pub fn all(&self) -> [(&'static str, u64); 11] {
        [
            ("InvalidState", self.invalid_state.load(Relaxed)),
            ("LoginFailures", self.login_failures.load(Relaxed)),
            ("AccessDenied", self.access_denied.load(Relaxed)),
            ("BadArguments", self.bad_arguments.load(Relaxed)),
            ("FailedCalls", self.failed_calls.load(Relaxed)),
            ("ModbusExceptions", self.modbus_exceptions.load(Relaxed)),
            ("ModbusBadFrames", self.modbus_bad_frames.load(Relaxed)),
            ("ModbusRefusedConnections", self.modbus_refused_connections.load(Relaxed)),
            ("PicksSent", self.picks_sent.load(Relaxed)),
            ("RecipesLoaded", self.recipes_loaded.load(Relaxed)),
            ("RecipesRefused", self.recipes_refused.load(Relaxed)),
        ]
    }

    /// The counters into `out` (its header is the caller's).
    pub fn write_status(&self, out: &mut LineStatus) {
        let gauge = |v: &AtomicU64| u32::try_from(v.load(Relaxed)).unwrap_or(u32::MAX);
        out.opcua_sessions = gauge(&self.opcua_sessions);
        out.modbus_connections = gauge(&self.modbus_connections);
        out.login_failures = self.login_failures.load(Relaxed);
        out.access_denied = self.access_denied.load(Relaxed);
        out.bad_arguments = self.bad_arguments.load(Relaxed);
        out.invalid_state = self.invalid_state.load(Relaxed);
        out.failed_calls = self.failed_calls.load(Relaxed);
        out.modbus_exceptions = self.modbus_exceptions.load(Relaxed);
        out.modbus_bad_frames = self.modbus_bad_frames.load(Relaxed);
        out.modbus_refused_connections = self.modbus_refused_connections.load(Relaxed);
        out.picks_sent = self.picks_sent.load(Relaxed);
        out.recipes_loaded = self.recipes_loaded.load(Relaxed);
        out.recipes_refused = self.recipes_refused.load(Relaxed);
    }
}

impl ClientCounters for LineCounters {
    fn pick_sent(&self) {
        Self::count(&self.picks_sent);
    }

    fn recipe_outcome(&self, loaded: bool) {
        Self::count(if loaded { &self.recipes_loaded } else { &self.recipes_refused });
    }

    fn publishes_line_status(&self) -> bool {
        true
    }

    fn write_line_status(&self, out: &mut LineStatus) {
        self.write_status(out);
    }
}
