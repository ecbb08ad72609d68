//! What the line refused, by kind: shown as `Rig.Line.*` over OPC UA and
//! printed when the line stops.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

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
}

impl LineCounters {
    pub fn count(counter: &AtomicU64) {
        counter.fetch_add(1, Relaxed);
    }

    /// (name, value) of each counter, for display.
    pub fn all(&self) -> [(&'static str, u64); 8] {
        [
            ("InvalidState", self.invalid_state.load(Relaxed)),
            ("LoginFailures", self.login_failures.load(Relaxed)),
            ("AccessDenied", self.access_denied.load(Relaxed)),
            ("BadArguments", self.bad_arguments.load(Relaxed)),
            ("FailedCalls", self.failed_calls.load(Relaxed)),
            ("ModbusExceptions", self.modbus_exceptions.load(Relaxed)),
            ("ModbusBadFrames", self.modbus_bad_frames.load(Relaxed)),
            ("ModbusRefusedConnections", self.modbus_refused_connections.load(Relaxed)),
        ]
    }
}
