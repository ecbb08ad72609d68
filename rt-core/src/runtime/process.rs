//! The real-time core process (DESIGN.md §3): a motor thread (SCHED_FIFO,
//! highest), a solver thread (SCHED_FIFO, below it), the iceoryx2 receiver
//! thread (SCHED_FIFO between them on the motor's CPU in event mode, else
//! normal priority) and the io thread (the caller's, normal priority) that
//! publishes Schedule and Telemetry and handles SIGINT/SIGTERM through
//! iceoryx2's node.

use core::sync::atomic::Ordering::Relaxed;
use core::time::Duration;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc;

use iceoryx2::node::{NodeView, NodeWaitFailure};
use iceoryx2::prelude::*;
use ipc_types::ports::{config_with_prefix, open_pub_sub};
use ipc_types::rig_node::rig_node;
use ipc_types::{CoreState, PartStates, Schedule, Telemetry, monotonic_now_ns, service_names};

use super::alloc_count;
use super::clock::{Clock, MonotonicClock};
use super::handoff::{StagedMotion, motion_handoff};
use super::inbox::{INBOUND_RING, InboxBuffers, Received, RingInbox, drain, forward};
use super::ipc_inbox::IpcInbox;
use super::latency::LatencyHistograms;
use super::motor::{MotorLoop, TruthFill, TruthTap};
use super::params::{CoreParams, ReceiverWake};
use super::rt_setup::{
    RT_STACK_BYTES, ThreadPlacement, lock_memory, make_current_thread_realtime,
    make_current_thread_realtime_on, pin_current_thread, prefault_stack,
};
use super::samples::{MOTOR_RING, MotorSample, SCHEDULE_RING, SOLVER_RING, SolverSample};
use super::shared::CoreShared;
use super::solve_stage::SolveStage;
use super::start_error::StartError;
use super::wake_budget::WakeBudget;
use crate::driver::PlateDriver;
use crate::motion::{PlateMotion, Rig};

/// The iceoryx2 node name of the core's io thread; a second core on the
/// same prefix finds it alive and refuses to start.
pub const CORE_NODE_NAME: &str = "upm-core";

/// How a run is set up besides [`CoreParams`].
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// iceoryx2 service prefix of the rig.
    pub prefix: String,
    /// Where `*.hgrm` go at exit (`None`: not written).
    pub histogram_dir: Option<PathBuf>,
    /// Stop by itself after this long (`None`: until SIGINT/SIGTERM).
    pub duration: Option<Duration>,
    /// Ground truth published on `upm/sim/ground_truth` at this rate (Hz);
    /// 0 = off. Only meaningful with a simulator driver and a `truth` fill.
    pub truth_hz: f64,
}

/// What the run achieved, for the caller to report.
#[derive(Debug, Clone)]
pub struct RunReport {
    pub telemetry: Telemetry,
    pub histograms: LatencyHistograms,
    pub realtime: RealtimeStatus,
    /// Samples the RT threads dropped because a ring was full.
    pub dropped_samples: u64,
}

/// Which real-time measures took effect.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RealtimeStatus {
    pub memory_locked: bool,
    pub motor: ThreadPlacement,
    pub solver: ThreadPlacement,
    /// The iceoryx2 receiver thread (SCHED_FIFO only in event mode, and only
    /// pinned to the motor's CPU).
    pub receiver: ThreadPlacement,
    pub allocations_counted: bool,
}

impl RealtimeStatus {
    pub fn flags(&self) -> u32 {
        let mut f = 0;
        if self.memory_locked {
            f |= Telemetry::RT_MEMORY_LOCKED;
        }
        if self.motor.fifo {
            f |= Telemetry::RT_MOTOR_FIFO;
        }
        if self.solver.fifo {
            f |= Telemetry::RT_SOLVER_FIFO;
        }
        if self.allocations_counted {
            f |= Telemetry::RT_ALLOCATIONS_COUNTED;
        }
        if self.motor.pinned {
            f |= Telemetry::RT_MOTOR_PINNED;
        }
        if self.receiver.fifo {
            f |= Telemetry::RT_RECEIVER_FIFO;
        }
        f
    }

    /// True when the loops run with real-time guarantees.
    pub fn is_realtime(&self) -> bool {
        self.memory_locked && self.motor.fifo && self.solver.fifo
    }
}

/// True if a live upm-core owns `prefix` (dead cores' resources are
/// cleaned up on the way).
pub fn core_running(prefix: &str) -> Result<bool, StartError> {
    let config = config_with_prefix(prefix).map_err(|_| StartError::Prefix)?;
    Ok(claim_prefix(&config) == Err(StartError::AlreadyRunning))
}

/// Refuse to start if a live core owns `config`'s prefix; clean up the
/// resources of dead ones (a core killed with SIGKILL).
fn claim_prefix(config: &Config) -> Result<(), StartError> {
    let mut alive = false;
    let listed = Node::<ipc::Service>::list(config, |state| {
        match state {
            NodeState::Alive(view) => {
                if view.details().as_ref().is_some_and(|d| d.name().as_str() == CORE_NODE_NAME) {
                    alive = true;
                }
            }
            NodeState::Dead(view) => {
                // Best effort: a failure leaves files iceoryx2 retries later.
                let _ = view.try_remove_stale_resources();
            }
            NodeState::Inaccessible(_) | NodeState::Undefined(_) => {}
        }
        CallbackProgression::Continue
    });
    if let Err(e) = listed {
        return Err(StartError::NodeList(e));
    }
    if alive { Err(StartError::AlreadyRunning) } else { Ok(()) }
}

/// Run the core with `driver` until SIGINT/SIGTERM (or `options.duration`).
/// On the way out the plate is brought home at a cycle boundary, the final
/// telemetry is published and the histograms are returned (and written).
pub fn run_core<D: PlateDriver + Send + 'static>(
    params: &CoreParams,
    driver: D,
    options: &RunOptions,
) -> Result<RunReport, StartError> {
    run_core_with_truth(params, driver, None, options)
}

/// [`run_core`] that also publishes the driver's ground truth (a
/// simulator's parts) through `truth` at `options.truth_hz`.
pub fn run_core_with_truth<D: PlateDriver + Send + 'static>(
    params: &CoreParams,
    driver: D,
    truth: Option<TruthFill<D>>,
    options: &RunOptions,
) -> Result<RunReport, StartError> {
    params.validate().map_err(StartError::Params)?;
    let config = config_with_prefix(&options.prefix).map_err(|_| StartError::Prefix)?;
    claim_prefix(&config)?;
    let node = rig_node(&options.prefix, Some(CORE_NODE_NAME), SignalHandlingMode::HandleTerminationRequests)
        .map_err(StartError::Node)?;
    let schedule_pub = open_pub_sub::<Schedule>(&node, service_names::SCHEDULE)
        .map_err(|error| StartError::Service { service: service_names::SCHEDULE, error })?
        .publisher_builder()
        .create()
        .map_err(|_| StartError::Port { service: service_names::SCHEDULE })?;
    let telemetry_pub = open_pub_sub::<Telemetry>(&node, service_names::TELEMETRY)
        .map_err(|error| StartError::Service { service: service_names::TELEMETRY, error })?
        .publisher_builder()
        .create()
        .map_err(|_| StartError::Port { service: service_names::TELEMETRY })?;

    let mut realtime = RealtimeStatus {
        memory_locked: params.rt.lock_memory && lock_memory(),
        allocations_counted: alloc_count::counter_installed(),
        ..RealtimeStatus::default()
    };
    let rig = Rig::new(params.rig).map_err(|e| StartError::Params(super::params::CoreParamsError::Rig(e)))?;
    let empty = PlateMotion::new(params.motion)
        .map_err(|e| StartError::Params(super::params::CoreParamsError::Motion(e)))?;
    let (writer, reader) = motion_handoff(&StagedMotion { motion: empty, request_seq: 0, frame_stamp_ns: 0 });
    let shared = Arc::new(CoreShared::new());
    let (motor_tx, mut motor_rx) = rtrb::RingBuffer::<MotorSample>::new(MOTOR_RING);
    let (solver_tx, mut solver_rx) = rtrb::RingBuffer::<SolverSample>::new(SOLVER_RING);
    let (schedule_tx, mut schedule_rx) = rtrb::RingBuffer::<Schedule>::new(SCHEDULE_RING);
    let truth_every = if options.truth_hz > 0.0 && options.truth_hz.is_finite() {
        ((params.motion.tick_hz / options.truth_hz).round() as u64).max(1)
    } else {
        0
    };
    let (truth_tap, mut truth_rx, truth_pub) = match truth {
        Some(fill) if truth_every > 0 => {
            let (input, output) = triple_buffer::triple_buffer(&PartStates::new());
            let publisher = open_pub_sub::<PartStates>(&node, service_names::SIM_GROUND_TRUTH)
                .map_err(|error| StartError::Service { service: service_names::SIM_GROUND_TRUTH, error })?
                .publisher_builder()
                .create()
                .map_err(|_| StartError::Port { service: service_names::SIM_GROUND_TRUTH })?;
            (Some(TruthTap { every: truth_every, fill, out: input }), Some(output), Some(publisher))
        }
        _ => (None, None, None),
    };

    // Receiver thread (not an RT hot path): iceoryx2 `receive()` allocates
    // when a publisher connects, so it runs here and feeds the solver a ring.
    let (inbound_tx, inbound_rx) = rtrb::RingBuffer::<Received>::new(INBOUND_RING);
    let motor_fifo = Arc::new(core::sync::atomic::AtomicBool::new(false));
    let (rx_ready_tx, rx_ready_rx) = mpsc::channel::<Result<ThreadPlacement, StartError>>();
    let receiver_thread = {
        let (shared, prefix, poll_ns, wake, motor_cpu, solver_cpu, motor_fifo) = (
            shared.clone(),
            options.prefix.clone(),
            params.solver_poll_ns,
            params.rt.receiver,
            params.rt.motor_cpu,
            params.rt.solver_cpu,
            motor_fifo.clone(),
        );
        let rx_priority = params.rt.receiver_priority;
        std::thread::Builder::new()
            .name("upm-ipc-rx".into())
            .spawn(move || {
                // Woken at real-time priority it is not queued behind a
                // solve; on the motor's CPU it never delays the solver, and the
                // motor preempts it. Only there: if the motor is unpinned or
                // shares the solver's CPU, or the pin or SCHED_FIFO is refused,
                // it stays a normal thread.
                let mut placement = ThreadPlacement::default();
                if let (ReceiverWake::Event, Some(cpu)) = (wake, motor_cpu)
                    && rx_priority > 0
                    && solver_cpu != Some(cpu)
                {
                    placement = make_current_thread_realtime_on(rx_priority, cpu);
                }
                let mut inbox = match IpcInbox::new(&prefix) {
                    Ok(i) => i,
                    Err(e) => {
                        let _ = rx_ready_tx.send(Err(e));
                        return;
                    }
                };
                let _ = rx_ready_tx.send(Ok(placement));
                let mut ring = inbound_tx;
                let mut buf = InboxBuffers::default();
                // Without a wake-up, look twice per solver period.
                let poll = Duration::from_nanos((poll_ns / 2).max(50_000));
                let mut placed = false;
                let mut wakes = WakeBudget::new();
                while !shared.stop.load(Relaxed) {
                    // Spinning shares the motor's CPU, once the motor is known to
                    // be SCHED_FIFO (it then preempts the spin at once; on the
                    // solver's CPU a solve would stall it). A motor without
                    // real-time rights keeps its CPU to itself.
                    if wake == ReceiverWake::Spin && !placed && motor_fifo.load(Relaxed) {
                        if let Some(cpu) = motor_cpu {
                            pin_current_thread(cpu);
                        }
                        placed = true;
                    }
                    let dropped = forward(&mut inbox, &mut buf, &mut ring);
                    shared.rejected_requests.fetch_add(dropped, Relaxed);
                    match wake {
                        ReceiverWake::Event => {
                            wakes.pace();
                            inbox.wait(poll);
                        }
                        ReceiverWake::Spin => core::hint::spin_loop(),
                    }
                }
            })
            .map_err(|_| StartError::Thread { thread: "ipc receiver" })?
    };
    match rx_ready_rx.recv() {
        Ok(Ok(placement)) => realtime.receiver = placement,
        Ok(Err(e)) => {
            let _ = receiver_thread.join();
            return Err(e);
        }
        Err(_) => return Err(StartError::ThreadStartup { thread: "ipc receiver" }),
    }

    // Solver thread: the solver is built (and warmed up) on its own thread.
    let (ready_tx, ready_rx) = mpsc::channel::<Result<ThreadPlacement, StartError>>();
    let solver_thread = {
        let (params, shared, rig) = (params.clone(), shared.clone(), rig.clone());
        std::thread::Builder::new()
            .name("upm-solver".into())
            .stack_size(RT_STACK_BYTES)
            .spawn(move || {
                let placement = make_current_thread_realtime(params.rt.solver_priority, params.rt.solver_cpu);
                prefault_stack();
                let mut stage =
                    match SolveStage::new(&params, rig, writer, shared.clone(), schedule_tx, solver_tx) {
                        Ok(s) => s,
                        Err(e) => {
                            let _ = ready_tx.send(Err(StartError::Params(e)));
                            return;
                        }
                    };
                let mut inbox = RingInbox(inbound_rx);
                let mut buf = InboxBuffers::default();
                let _ = ready_tx.send(Ok(placement));
                let clock = MonotonicClock;
                alloc_count::mark_rt_thread(true);
                let mut deadline = clock.now_ns();
                while !shared.stop.load(Relaxed) {
                    drain(&mut inbox, &mut stage, &mut buf, &clock);
                    deadline += params.solver_poll_ns;
                    let now = clock.now_ns();
                    if deadline < now {
                        deadline = now;
                    }
                    clock.sleep_until(deadline);
                }
                alloc_count::mark_rt_thread(false);
            })
            .map_err(|_| StartError::Thread { thread: "solver" })?
    };
    realtime.solver = match ready_rx.recv() {
        Ok(Ok(p)) => p,
        Ok(Err(e)) => {
            let _ = solver_thread.join();
            shared.stop.store(true, Relaxed);
            let _ = receiver_thread.join();
            return Err(e);
        }
        Err(_) => {
            shared.stop.store(true, Relaxed);
            let _ = receiver_thread.join();
            return Err(StartError::ThreadStartup { thread: "solver" });
        }
    };

    // Motor thread.
    let (ready_tx, ready_rx) = mpsc::channel::<ThreadPlacement>();
    let motor_thread = {
        let (p, motor_shared) = (params.clone(), shared.clone());
        let period = params.tick_ns();
        let thread = std::thread::Builder::new()
            .name("upm-motor".into())
            .stack_size(RT_STACK_BYTES)
            .spawn(move || {
                let placement = make_current_thread_realtime(p.rt.motor_priority, p.rt.motor_cpu);
                prefault_stack();
                let mut motor = MotorLoop::new(
                    driver,
                    rig,
                    reader,
                    motor_shared,
                    motor_tx,
                    p.parts_max_age_ns,
                    p.request_max_age_ns,
                );
                if let Some(tap) = truth_tap {
                    motor.set_truth_tap(tap);
                }
                let _ = ready_tx.send(placement);
                alloc_count::mark_rt_thread(true);
                motor.run(&MonotonicClock, period);
                alloc_count::mark_rt_thread(false);
                motor.dropped_samples()
            })
            .map_err(|_| StartError::Thread { thread: "motor" });
        match thread {
            Ok(t) => t,
            Err(e) => {
                shared.stop.store(true, Relaxed);
                let _ = (solver_thread.join(), receiver_thread.join());
                return Err(e);
            }
        }
    };
    realtime.motor = match ready_rx.recv() {
        Ok(p) => p,
        Err(_) => {
            shared.stop.store(true, Relaxed);
            let _ = (motor_thread.join(), solver_thread.join(), receiver_thread.join());
            return Err(StartError::ThreadStartup { thread: "motor" });
        }
    };
    motor_fifo.store(realtime.motor.fifo, Relaxed);

    // io loop on this thread.
    let start_ns = monotonic_now_ns();
    let stop_at = options.duration.map(|d| start_ns.saturating_add(d.as_nanos() as u64));
    let mut histograms = LatencyHistograms::default();
    let mut telemetry = Telemetry::new();
    telemetry.core_pid = std::process::id();
    telemetry.realtime_flags = realtime.flags();
    let mut next_telemetry = start_ns;
    let io_period = Duration::from_millis(2);
    let mut publish = |hist: &mut LatencyHistograms, tel: &mut Telemetry, force: bool| {
        while let Ok(s) = motor_rx.pop() {
            hist.record_motor(&s);
        }
        while let Ok(s) = solver_rx.pop() {
            hist.record_solver(&s);
        }
        while let Ok(s) = schedule_rx.pop() {
            let _ = schedule_pub.send_copy(s);
        }
        if let (Some(rx), Some(p)) = (truth_rx.as_mut(), truth_pub.as_ref())
            && rx.update()
        {
            let _ = p.send_copy(*rx.peek_output_buffer());
        }
        let now = monotonic_now_ns();
        if force || now >= next_telemetry {
            next_telemetry = now + params.telemetry_period_ns;
            fill_telemetry(tel, &shared, hist, now, start_ns);
            let _ = telemetry_pub.send_copy(*tel);
        }
    };
    loop {
        publish(&mut histograms, &mut telemetry, false);
        if stop_at.is_some_and(|t| monotonic_now_ns() >= t) {
            break;
        }
        match node.wait(io_period) {
            Ok(()) => {}
            Err(NodeWaitFailure::Interrupt | NodeWaitFailure::TerminationRequest) => break,
        }
    }
    // Stop: the motor ends at a cycle boundary with the plate home.
    shared.stop.store(true, Relaxed);
    let dropped_samples = motor_thread.join().unwrap_or(0);
    let _ = solver_thread.join();
    let _ = receiver_thread.join();
    shared.set_state(CoreState::Idle);
    publish(&mut histograms, &mut telemetry, true);
    if let Some(dir) = &options.histogram_dir {
        // Reported, not fatal: the plate is already home.
        if let Err(e) = histograms.write_hgrm_dir(dir) {
            eprintln!("upm-core: cannot write histograms to {}: {e}", dir.display());
        }
    }
    Ok(RunReport { telemetry, histograms, realtime, dropped_samples })
}

/// Snapshot the shared state into a telemetry message.
pub fn fill_telemetry(
    t: &mut Telemetry,
    shared: &CoreShared,
    hist: &LatencyHistograms,
    now: u64,
    start_ns: u64,
) {
    t.seq += 1;
    t.stamp_ns = now;
    t.set_core_state(shared.state());
    t.cycle = shared.cycle.load(Relaxed);
    let [x, y, theta] = shared.pose();
    (t.plate_x, t.plate_y, t.plate_theta) = (x, y, theta);
    t.counters = shared.counters();
    t.counters.rt_thread_allocations =
        alloc_count::rt_allocations().saturating_sub(shared.allocation_baseline.load(Relaxed));
    let age = |stamp: u64| {
        let since = if stamp == 0 { start_ns } else { stamp };
        now.saturating_sub(since) as f64 / 1e6
    };
    t.parts_age_ms = age(shared.parts_stamp_ns.load(Relaxed));
    t.request_age_ms = age(shared.request_stamp_ns.load(Relaxed));
    t.latency = hist.core_latencies();
}
