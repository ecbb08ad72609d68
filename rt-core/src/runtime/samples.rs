//! Latency samples the RT threads push, wait-free, into preallocated rings
//! for the io thread to record into histograms.

/// One motor tick.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MotorSample {
    /// Wake-up lateness against the absolute deadline (ns).
    pub wakeup_ns: u64,
    /// Work done in the tick: read → update → write (ns).
    pub tick_ns: u64,
    /// Camera frame → schedule active, when this tick swapped in a new
    /// schedule (ns); 0 otherwise.
    pub frame_to_active_ns: u64,
}

/// One handled solver-thread message.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolverSample {
    /// Solve + motion build + limit check (ns); 0 for part states.
    pub solve_ns: u64,
    /// PartStates stamp → received by the core's receiver thread (ns); 0
    /// for requests.
    pub ipc_ns: u64,
    /// Received → validated on the solver thread (the solver's poll), ns;
    /// 0 for requests.
    pub pickup_ns: u64,
}

/// Ring capacity (samples) between a motor thread and the io thread: one
/// second at 10 kHz, so an io thread stalled for up to a second loses none.
pub const MOTOR_RING: usize = 16_384;
/// Ring capacity for solver samples and schedules.
pub const SOLVER_RING: usize = 1024;
pub const SCHEDULE_RING: usize = 64;
