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
/// Ring capacity for rejections on their way to the sender; a flood beyond
/// it is still counted by reason, only not answered one by one.
pub const REJECTION_RING: usize = 256;

/// Where a solve stage's results go: to the io thread, which publishes
/// them. Every ring is pushed without blocking (a full ring drops).
#[derive(Debug)]
pub struct StageOutputs {
    pub schedules: rtrb::Producer<ipc_types::Schedule>,
    pub samples: rtrb::Producer<SolverSample>,
    pub rejections: rtrb::Producer<ipc_types::Rejection>,
}

/// The io thread's ends of [`StageOutputs`].
#[derive(Debug)]
pub struct StageOutputsRx {
    pub schedules: rtrb::Consumer<ipc_types::Schedule>,
    pub samples: rtrb::Consumer<SolverSample>,
    pub rejections: rtrb::Consumer<ipc_types::Rejection>,
}

impl StageOutputs {
    /// The rings, allocated once at start-up.
    pub fn rings() -> (Self, StageOutputsRx) {
        let (schedules, schedules_rx) = rtrb::RingBuffer::new(SCHEDULE_RING);
        let (samples, samples_rx) = rtrb::RingBuffer::new(SOLVER_RING);
        let (rejections, rejections_rx) = rtrb::RingBuffer::new(REJECTION_RING);
        (
            Self { schedules, samples, rejections },
            StageOutputsRx { schedules: schedules_rx, samples: samples_rx, rejections: rejections_rx },
        )
    }
}
