//! The real-time core (ARCHITECTURE.md §3–5): a motor loop that plays closed plate
//! motions through a [`upm_hardware::PlateDriver`], a solver stage that turns
//! validated messages into those motions, the wait-free hand-over between
//! them, and the process that runs them on SCHED_FIFO threads over iceoryx2.
//!
//! The same [`MotorLoop`] and [`SolveStage`] run in [`lockstep`] (one
//! thread, injected [`ManualClock`]) for bit-identical tests, and in
//! [`run_core`] (real threads, [`MonotonicClock`]).

pub mod alloc_count;
mod clock;
mod doorbell;
mod driver_cell;
#[cfg(feature = "fault-injection")]
pub mod fault_injection;
mod handoff;
mod inbox;
mod ipc_inbox;
mod latency;
pub mod lockstep;
mod motor;
mod params;
mod plate_params;
mod process;
mod rejection_log;
mod rig_info;
mod rt_params;
pub mod rt_setup;
mod safety_params;
mod samples;
mod shared;
mod solve_stage;
mod stage_graph;
mod start_error;
mod thread_health;
mod wake_budget;

pub use alloc_count::RtAllocCounter;
pub use clock::{Clock, ManualClock, MonotonicClock};
pub use doorbell::Doorbell;
pub use handoff::{MotionReader, MotionWriter, StagedMotion, motion_handoff};
pub use inbox::{
    INBOUND_RING, Inbound, InboundMessage, Inbox, InboxBuffers, QueueInbox, Received, RingInbox, forward,
};
pub use ipc_inbox::IpcInbox;
pub use latency::{LatencyHistograms, percentiles, write_hgrm};
pub use motor::{MotorLoop, MotorPolicy, TickOutcome};
pub use params::{CoreParams, CoreParamsError};
pub use plate_params::PlateParams;
pub use process::{
    CORE_NODE_NAME, Changeovers, PickSink, RealtimeStatus, RecipeSink, RunOptions, RunReport,
    SimulatorOutputs, fill_telemetry, run_core, run_core_with_truth,
};
pub use rig_info::rig_info;
pub use rt_params::{ReceiverWake, RtParams};
pub use safety_params::{SafetyError, SafetyParams, TelemetryParams};
pub use samples::{MotorSample, SolverSample, StageOutputs, StageOutputsRx};
pub use shared::{CoreShared, HealthReport, InertiaReport};
pub use solve_stage::{RequestError, SolveStage};
pub use stage_graph::StageGraph;
pub use start_error::StartError;
pub use thread_health::CoreThread;
