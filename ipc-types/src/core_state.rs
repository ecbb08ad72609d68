//! The core's operating state, carried on the wire as a `u32` code.

crate::wire_code::wire_code! {
    /// Operating state of the core. On the wire ([`crate::Telemetry::state`])
    /// it is the `u32` code.
    pub enum CoreState {
        /// Ports up, no motion requested yet.
        Idle = 0 => "idle",
        /// Playing schedules.
        Running = 1 => "running",
        /// Inputs stale: the plate is held still until fresh input arrives.
        Hold = 2 => "hold",
        /// Stopped after an error; needs a restart.
        Fault = 3 => "fault",
    }
}
