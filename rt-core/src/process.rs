//! The real-time core process (ARCHITECTURE.md §3): a motor thread (SCHED_FIFO,
//! highest), a solver thread (SCHED_FIFO, below it), the iceoryx2 receiver
//! thread (SCHED_FIFO between them on the motor's CPU in event mode, else
//! normal priority) and the io thread (the caller's, normal priority) that
//! publishes RigInfo (once), Schedule and Telemetry and handles
//! SIGINT/SIGTERM through iceoryx2's node.

use core::sync::atomic::AtomicBool;
use core::sync::atomic::Ordering::Relaxed;
use core::time::Duration;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc;
use std::thread::JoinHandle;

use iceoryx2::node::NodeWaitFailure;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::prelude::*;
use ipc_types::ports::config_with_prefix;
use ipc_types::rig_node::rig_node;
use ipc_types::{
    CoreState, HealthSource, PartStates, RejectReason, RejectedKind, Rejection, RigInfo, Schedule, Telemetry,
    monotonic_now_ns, service_names,
};

use super::alloc_count;
use super::clock::MonotonicClock;
use super::inbox::{INBOUND_RING, InboxBuffers, Received, RingInbox, forward};
use super::ipc_inbox::IpcInbox;
use super::latency::LatencyHistograms;
use super::motor::MotorLoop;
use super::params::CoreParams;
use super::rejection_log::RejectionLog;
use super::rt_params::ReceiverWake;
use super::rt_setup::{
    RT_STACK_BYTES, ThreadPlacement, hold_cpu_dma_latency, keep_current_thread_off, lock_memory,
    make_current_thread_realtime, make_current_thread_realtime_on, pin_current_thread, prefault_stack,
};
use super::shared::{CoreShared, HealthReport, InertiaReport};
use super::solve_stage::SolveStage;
use super::stage_graph::StageGraph;
use super::start_error::StartError;
use super::thread_health::CoreThread;
use super::wake_budget::WakeBudget;
use upm_hardware::PlateDriver;

/// The iceoryx2 node name of the core's io thread; a second core on the
/// same prefix finds it alive and refuses to start.
pub const CORE_NODE_NAME: &str = ipc_types::discovery::CORE_NODE;

/// How a run is set up besides [`CoreParams`].
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// iceoryx2 service prefix of the rig.
    pub prefix: String,
    /// Where `*.hgrm` go at exit (`None`: not written).
    pub histogram_dir: Option<PathBuf>,
    /// Stop by itself after this long (`None`: until SIGINT/SIGTERM).
    pub duration: Option<Duration>,
    /// The rate vision publishes PartStates at (Hz), told to clients in
    /// `RigInfo`; 0: not known.
    pub vision_frame_hz: f64,
}

/// What the run achieved, for the caller to report.
#[derive(Debug, Clone)]
pub struct RunReport {
    pub telemetry: Telemetry,
    pub histograms: LatencyHistograms,
    pub realtime: RealtimeStatus,
    /// Samples the RT threads dropped because a ring was full.
    pub dropped_samples: u64,
    /// Set when a core thread died: which, and why. The run then failed.
    pub fault: Option<HealthReport>,
    /// The plate's mass and inertia as the feed-forward ended with them.
    pub inertia: InertiaReport,
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
    /// A PM QoS request was asked for (`rt.cpu_dma_latency_us`) …
    pub pm_qos_requested: bool,
    /// … and is held.
    pub pm_qos_held: bool,
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
        if self.pm_qos_held {
            f |= Telemetry::RT_PM_QOS_HELD;
        }
        f
    }

    /// True when the loops run with real-time guarantees.
    pub fn is_realtime(&self) -> bool {
        self.memory_locked && self.motor.fifo && self.solver.fifo
    }
}

/// Refuse to start if a live core owns `config`'s prefix; clean up the
/// resources of dead ones (a core killed with SIGKILL).
fn claim_prefix(prefix: &str) -> Result<(), StartError> {
    match ipc_types::discovery::core_running(prefix) {
        Ok(true) => Err(StartError::AlreadyRunning),
        Ok(false) => Ok(()),
        Err(e) => Err(StartError::NodeList(e)),
    }
}

/// Run the core with `driver` until SIGINT/SIGTERM (or `options.duration`).
/// On the way out the plate is brought home at a cycle boundary, the final
/// telemetry is published and the histograms are returned (and written).
pub fn run_core<D: PlateDriver + Send + 'static>(
    params: &CoreParams,
    driver: D,
    options: &RunOptions,
) -> Result<RunReport, StartError> {
    run_core_with_truth(params, driver, SimulatorOutputs::default(), options)
}

/// Where the io thread hands each valid `PickCommand` (an external
/// robot's pick, to the feed cell).
pub type PickSink = Box<dyn FnMut(&ipc_types::PickCommand) + Send>;

/// Where the io thread hands each valid `RecipeCommand`'s path (a
/// changeover, for the feed cell): Ok once the cell switches at its next
/// step, else the one-line reason it will not (the running recipe stays).
pub type RecipeSink = Box<dyn FnMut(&str) -> Result<(), String> + Send>;

/// A feed cell's changeovers: the recipe it runs now, announced on
/// `upm/recipe/active` at start and after each changeover, and where a
/// new one goes.
pub struct Changeovers {
    pub running: ipc_types::RecipeCommand,
    pub sink: RecipeSink,
}

impl core::fmt::Debug for Changeovers {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "Changeovers(running: {:?})", self.running.path())
    }
}

/// What a simulated driver writes where it steps, for the io thread to
/// publish: its parts' ground truth (for the simulated camera) and its
/// feed cell's status.
#[derive(Default)]
pub struct SimulatorOutputs {
    /// Published on `upm/sim/ground_truth`.
    pub truth: Option<triple_buffer::Output<PartStates>>,
    /// Published on `upm/feed`.
    pub feed: Option<triple_buffer::Output<ipc_types::FeedStatus>>,
    /// Where each valid `PickCommand` of `upm/pick` goes (an external
    /// robot's picks, to the feed cell); the io thread reads them.
    pub picks: Option<PickSink>,
    /// The feed cell's changeovers (`upm/recipe`); the io thread reads them.
    pub recipes: Option<Changeovers>,
}

impl core::fmt::Debug for SimulatorOutputs {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "SimulatorOutputs(truth: {}, feed: {}, picks: {}, recipes: {})",
            self.truth.is_some(),
            self.feed.is_some(),
            self.picks.is_some(),
            self.recipes.is_some()
        )
    }
}

/// [`run_core`] that also publishes, from the io thread, what a simulated
/// driver writes into `outputs`.
///
/// If a core thread dies (panic, or its body returns), the motor holds the
/// plate at once, telemetry names the thread for `params.fault_exit_ns`,
/// and the run ends with [`RunReport::fault`] set.
pub fn run_core_with_truth<D: PlateDriver + Send + 'static>(
    params: &CoreParams,
    driver: D,
    outputs: SimulatorOutputs,
    options: &RunOptions,
) -> Result<RunReport, StartError> {
    params.validate().map_err(StartError::Params)?;
    config_with_prefix(&options.prefix).map_err(|_| StartError::Prefix)?;
    claim_prefix(&options.prefix)?;
    let node = rig_node(&options.prefix, Some(CORE_NODE_NAME), SignalHandlingMode::HandleTerminationRequests)
        .map_err(StartError::Node)?;
    // Seen by `upm status` without a prefix; best effort (a rig runs without).
    let announcement = ipc_types::discovery::announce_rig(&options.prefix).ok();
    let schedule_pub =
        ipc_types::ports::publisher::<Schedule>(&node, service_names::SCHEDULE).map_err(StartError::Port)?;
    let telemetry_pub = ipc_types::ports::publisher::<Telemetry>(&node, service_names::TELEMETRY)
        .map_err(StartError::Port)?;
    let rejection_pub = ipc_types::ports::publisher::<ipc_types::Rejection>(&node, service_names::REJECTION)
        .map_err(StartError::Port)?;
    let mut rejection_log = RejectionLog::default();
    // The rig describes itself once, before a client can need it. History 1
    // hands it to every later subscriber, on the publisher's next
    // update_connections (the io loop's every pass).
    let graph = StageGraph::build(params, driver).map_err(StartError::Params)?;
    let rig_info_pub =
        ipc_types::ports::publisher::<RigInfo>(&node, service_names::RIG_INFO).map_err(StartError::Port)?;
    let info = super::rig_info::rig_info(params, &graph.k_bounds, &options.prefix, options.vision_frame_hz);
    rig_info_pub.send_copy(info).map_err(|_| StartError::RigInfo)?;

    // Held until this function returns; the kernel drops it if the process dies.
    let pm_qos = params.rt.cpu_dma_latency_us.map(hold_cpu_dma_latency);
    let mut realtime = RealtimeStatus {
        memory_locked: params.rt.lock_memory && lock_memory(),
        allocations_counted: alloc_count::counter_installed(),
        pm_qos_requested: pm_qos.is_some(),
        pm_qos_held: matches!(pm_qos, Some(Ok(_))),
        ..RealtimeStatus::default()
    };
    if let Some(Err(e)) = &pm_qos {
        // Start-up, once: the one place the core explains a missing right.
        eprintln!(
            "upm-core: WARNING: cannot hold a PM QoS request on {} ({e}): idle CPUs may wake late, \
             and wake-up latency then measures the host's idle policy. Run as root or give the rig's \
             user write access (docs/deploy.md); rt.cpu_dma_latency_us = \"leave\" silences this.",
            super::rt_setup::CPU_DMA_LATENCY
        );
    }
    let StageGraph { motor, stage, shared, motor_samples: mut motor_rx, outputs: mut stage_rx, .. } = graph;
    let SimulatorOutputs {
        truth: mut truth_rx,
        feed: mut feed_rx,
        picks: mut pick_sink,
        recipes: mut changeovers,
    } = outputs;
    let recipe_ports = match changeovers.as_ref() {
        Some(c) => {
            let requests =
                ipc_types::ports::subscriber::<ipc_types::RecipeCommand>(&node, service_names::RECIPE)
                    .map_err(StartError::Port)?;
            let active =
                ipc_types::ports::publisher::<ipc_types::RecipeCommand>(&node, service_names::RECIPE_ACTIVE)
                    .map_err(StartError::Port)?;
            // History hands the running recipe to every later subscriber.
            active.send_copy(c.running).map_err(|_| StartError::RigInfo)?;
            Some((requests, active))
        }
        None => None,
    };
    let pick_sub = match pick_sink {
        Some(_) => Some(
            ipc_types::ports::subscriber::<ipc_types::PickCommand>(&node, service_names::PICK)
                .map_err(StartError::Port)?,
        ),
        None => None,
    };
    let truth_pub = match truth_rx {
        Some(_) => Some(
            ipc_types::ports::publisher::<PartStates>(&node, service_names::SIM_GROUND_TRUTH)
                .map_err(StartError::Port)?,
        ),
        None => None,
    };
    let feed_pub = match feed_rx {
        Some(_) => Some(
            ipc_types::ports::publisher::<ipc_types::FeedStatus>(&node, service_names::FEED)
                .map_err(StartError::Port)?,
        ),
        None => None,
    };

    let (inbound_tx, inbound_rx) = rtrb::RingBuffer::<Received>::new(INBOUND_RING);
    let motor_fifo = Arc::new(AtomicBool::new(false));
    let mut threads = CoreThreads::default();
    let (receiver_thread, placement) =
        spawn_receiver(params, &options.prefix, shared.clone(), inbound_tx, motor_fifo.clone())?;
    threads.receiver = Some(receiver_thread);
    realtime.receiver = placement;
    let solver = spawn_solver(params, stage, shared.clone(), inbound_rx);
    match solver {
        Ok((t, placement)) => {
            threads.solver = Some(t);
            realtime.solver = placement;
        }
        Err(e) => {
            threads.stop(&shared);
            return Err(e);
        }
    }
    match spawn_motor(params, motor, shared.clone()) {
        Ok((t, placement)) => {
            threads.motor = Some(t);
            realtime.motor = placement;
        }
        Err(e) => {
            threads.stop(&shared);
            return Err(e);
        }
    }
    motor_fifo.store(realtime.motor.fifo, Relaxed);
    // This (io) thread publishes, lists nodes and writes files: elsewhere,
    // until it returns to its caller.
    let io_cpus = match (params.rt.isolate_motor_cpu, realtime.motor.pinned, params.rt.motor_cpu) {
        (true, true, Some(cpu)) => keep_current_thread_off(cpu),
        _ => None,
    };

    // io loop on this thread.
    let start_ns = monotonic_now_ns();
    let stop_at = options.duration.map(|d| start_ns.saturating_add(d.as_nanos() as u64));
    let mut histograms = LatencyHistograms::default();
    let mut telemetry = Telemetry::new();
    telemetry.core_pid = std::process::id();
    telemetry.realtime_flags = realtime.flags();
    let mut next_telemetry = start_ns;
    let mut next_presence = start_ns;
    let mut fault_since: Option<u64> = None;
    let io_period = Duration::from_millis(2);
    let mut publish = |hist: &mut LatencyHistograms, tel: &mut Telemetry, force: bool| {
        while let Ok(s) = motor_rx.pop() {
            hist.record_motor(&s);
        }
        while let Ok(s) = stage_rx.samples.pop() {
            hist.record_solver(&s);
        }
        // A new subscriber gets the rig's description here.
        let _ = rig_info_pub.update_connections();
        while let Ok(s) = stage_rx.schedules.pop() {
            let _ = schedule_pub.send_copy(s);
        }
        while let Ok(r) = stage_rx.rejections.pop() {
            let _ = rejection_pub.send_copy(r);
            rejection_log.note(&r, r.stamp_ns);
        }
        if let (Some(rx), Some(p)) = (truth_rx.as_mut(), truth_pub.as_ref())
            && rx.update()
        {
            let _ = p.send_copy(*rx.peek_output_buffer());
        }
        if let (Some(rx), Some(p)) = (feed_rx.as_mut(), feed_pub.as_ref())
            && rx.update()
        {
            let _ = p.send_copy(*rx.peek_output_buffer());
        }
        if let (Some(sub), Some(sink)) = (pick_sub.as_ref(), pick_sink.as_mut()) {
            let limits = ipc_types::ValidationLimits::new([f64::INFINITY; 2], monotonic_now_ns());
            while let Ok(Some(s)) = sub.receive() {
                let c = *s.payload();
                match c.validate(&limits) {
                    Ok(()) => sink(&c),
                    Err(e) => {
                        shared.count_reject(e.reason());
                        let now = monotonic_now_ns();
                        let r = Rejection::new(
                            RejectedKind::PickCommand,
                            c.seq,
                            c.stamp_ns,
                            now,
                            e.reason(),
                            format_args!("{e}"),
                        );
                        let _ = rejection_pub.send_copy(r);
                        rejection_log.note(&r, now);
                    }
                }
            }
        }
        if let (Some((requests, active)), Some(c)) = (recipe_ports.as_ref(), changeovers.as_mut()) {
            // A new subscriber gets the running recipe here.
            let _ = active.update_connections();
            let limits = ipc_types::ValidationLimits::new([f64::INFINITY; 2], monotonic_now_ns());
            while let Ok(Some(s)) = requests.receive() {
                let command = *s.payload();
                let outcome = match command.validate(&limits) {
                    Ok(()) => (c.sink)(command.path().unwrap_or_default())
                        .map_err(|m| (ipc_types::RejectReason::BadRecipe, m)),
                    Err(e) => Err((e.reason(), e.to_string())),
                };
                match outcome {
                    Ok(()) => {
                        c.running = command;
                        let _ = active.send_copy(command);
                    }
                    Err((reason, message)) => {
                        shared.count_reject(reason);
                        let now = monotonic_now_ns();
                        let r = Rejection::new(
                            RejectedKind::RecipeCommand,
                            command.seq,
                            command.stamp_ns,
                            now,
                            reason,
                            format_args!("{message}"),
                        );
                        let _ = rejection_pub.send_copy(r);
                        rejection_log.note(&r, now);
                    }
                }
            }
        }
        let now = monotonic_now_ns();
        if force || now >= next_telemetry {
            next_telemetry = now + params.telemetry.period_ns;
            fill_telemetry(tel, &shared, hist, now, start_ns);
            let _ = telemetry_pub.send_copy(*tel);
        }
    };
    loop {
        let now = monotonic_now_ns();
        if now >= next_presence {
            // Walks iceoryx2's files: once a second, on this thread only.
            next_presence = now + 1_000_000_000;
            fill_clients(&mut telemetry, &options.prefix);
        }
        if shared.thread_died() {
            // The motor (if it lives) holds; say so for a while, then exit.
            shared.set_state(CoreState::Fault);
            let since = *fault_since.get_or_insert(now);
            if now.saturating_sub(since) >= params.safety.fault_exit_ns {
                break;
            }
        }
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
    let dropped_samples = threads.stop(&shared);
    let fault = shared.thread_died().then(|| shared.health());
    if fault.is_none() {
        shared.set_state(CoreState::Idle);
    }
    publish(&mut histograms, &mut telemetry, true);
    drop((announcement, pm_qos));
    if let Some(set) = &io_cpus {
        super::rt_setup::restore_current_thread_cpus(set);
    }
    if let Some(dir) = &options.histogram_dir {
        // Reported, not fatal: the plate is already home.
        if let Err(e) = histograms.write_hgrm_dir(dir) {
            eprintln!("upm-core: cannot write histograms to {}: {e}", dir.display());
        }
    }
    Ok(RunReport { telemetry, histograms, realtime, dropped_samples, fault, inertia: shared.inertia() })
}

/// The vision and planner clients on `prefix` (0 when absent).
fn fill_clients(t: &mut Telemetry, prefix: &str) {
    use ipc_types::discovery::{PLANNER_NODE, VISION_NODE, live_nodes};
    // One walk of the registry; a failed one reads as "no clients".
    let nodes = live_nodes(prefix, "").unwrap_or_default();
    let newest = |role: &str| {
        nodes.iter().rev().find(|n| n.name.starts_with(role)).map_or((0, 0), |n| (n.pid, n.started_ns))
    };
    (t.vision_pid, t.vision_started_ns) = newest(VISION_NODE);
    (t.planner_pid, t.planner_started_ns) = newest(PLANNER_NODE);
}

/// The core's three threads; a thread that died (parked in the panic hook)
/// is left behind, never joined.
#[derive(Default)]
struct CoreThreads {
    receiver: Option<JoinHandle<()>>,
    solver: Option<JoinHandle<()>>,
    motor: Option<JoinHandle<u64>>,
}

impl CoreThreads {
    /// Ask every thread to stop and join those that end within a few
    /// seconds (the motor finishes its cycle first). Returns the motor's
    /// dropped samples.
    fn stop(&mut self, shared: &CoreShared) -> u64 {
        shared.stop.store(true, Relaxed);
        shared.solver_doorbell.ring();
        let deadline = std::time::Instant::now() + Duration::from_secs(5);
        let dropped = join_by(self.motor.take(), deadline).unwrap_or(0);
        join_by(self.solver.take(), deadline);
        join_by(self.receiver.take(), deadline);
        dropped
    }
}

fn join_by<T>(handle: Option<JoinHandle<T>>, deadline: std::time::Instant) -> Option<T> {
    let handle = handle?;
    while !handle.is_finished() {
        if std::time::Instant::now() >= deadline {
            return None;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    handle.join().ok()
}

/// The iceoryx2 receiver thread (not an RT hot path): `receive()` allocates
/// when a publisher connects, so it runs here and feeds the solver a ring.
fn spawn_receiver(
    params: &CoreParams,
    prefix: &str,
    shared: Arc<CoreShared>,
    mut ring: rtrb::Producer<Received>,
    motor_fifo: Arc<AtomicBool>,
) -> Result<(JoinHandle<()>, ThreadPlacement), StartError> {
    let (ready_tx, ready_rx) = mpsc::channel::<Result<ThreadPlacement, StartError>>();
    let (prefix, poll_ns, rt) = (prefix.to_owned(), params.rt.solver_poll_ns, params.rt);
    let thread = std::thread::Builder::new()
        .name("upm-ipc-rx".into())
        .spawn(move || {
            let _guard = CoreThread::enter(HealthSource::ReceiverThread, shared.clone());
            // Woken at real-time priority it is not queued behind a
            // solve; on the motor's CPU it never delays the solver, and the
            // motor preempts it. Only there: if the motor is unpinned or
            // shares the solver's CPU, or the pin or SCHED_FIFO is refused,
            // it stays a normal thread.
            let mut placement = ThreadPlacement::default();
            if let (ReceiverWake::Event, Some(cpu)) = (rt.receiver, rt.motor_cpu)
                && rt.receiver_priority > 0
                && rt.solver_cpu != Some(cpu)
            {
                placement = make_current_thread_realtime_on(rt.receiver_priority, cpu);
            }
            let mut inbox = match IpcInbox::new(&prefix) {
                Ok(i) => i,
                Err(e) => {
                    let _ = ready_tx.send(Err(e));
                    shared.stop.store(true, Relaxed);
                    return;
                }
            };
            let _ = ready_tx.send(Ok(placement));
            #[cfg(feature = "fault-injection")]
            let inject = super::fault_injection::FaultPlan::from_env();
            let mut buf = InboxBuffers::default();
            // Without a wake-up, look twice per solver period.
            let poll = Duration::from_nanos((poll_ns / 2).max(50_000));
            let mut placed = false;
            let mut wakes = WakeBudget::new();
            let mut receive_errors = 0;
            while !shared.stop.load(Relaxed) {
                #[cfg(feature = "fault-injection")]
                inject.panic_if_due(HealthSource::ReceiverThread, monotonic_now_ns());
                // Spinning shares the motor's CPU, once the motor is known to
                // be SCHED_FIFO (it then preempts the spin at once; on the
                // solver's CPU a solve would stall it). A motor without
                // real-time rights keeps its CPU to itself.
                if rt.receiver == ReceiverWake::Spin && !placed && motor_fifo.load(Relaxed) {
                    if let Some(cpu) = rt.motor_cpu {
                        pin_current_thread(cpu);
                    }
                    placed = true;
                }
                let (forwarded, dropped) = forward(&mut inbox, &mut buf, &mut ring);
                if forwarded > 0 {
                    shared.solver_doorbell.ring();
                }
                shared.rejected_requests.fetch_add(dropped, Relaxed);
                shared.count_rejects(RejectReason::Overflow, dropped);
                shared.count_rejects(RejectReason::ReceiveError, inbox.receive_errors - receive_errors);
                receive_errors = inbox.receive_errors;
                match rt.receiver {
                    ReceiverWake::Event => {
                        wakes.pace();
                        inbox.wait(poll);
                    }
                    ReceiverWake::Spin => core::hint::spin_loop(),
                }
            }
        })
        .map_err(|_| StartError::Thread { thread: "ipc receiver" })?;
    match ready_rx.recv() {
        Ok(Ok(placement)) => Ok((thread, placement)),
        Ok(Err(e)) => {
            let _ = thread.join();
            Err(e)
        }
        Err(_) => Err(StartError::ThreadStartup { thread: "ipc receiver" }),
    }
}

/// The solver thread, serving `stage` (built and warmed up by the
/// [`StageGraph`]) until stop.
fn spawn_solver(
    params: &CoreParams,
    mut stage: SolveStage,
    shared: Arc<CoreShared>,
    inbound: rtrb::Consumer<Received>,
) -> Result<(JoinHandle<()>, ThreadPlacement), StartError> {
    let (ready_tx, ready_rx) = mpsc::channel::<ThreadPlacement>();
    let rt = params.rt;
    let thread = std::thread::Builder::new()
        .name("upm-solver".into())
        .stack_size(RT_STACK_BYTES)
        .spawn(move || {
            let _guard = CoreThread::enter(HealthSource::SolverThread, shared.clone());
            let placement = make_current_thread_realtime(rt.solver_priority, rt.solver_cpu);
            prefault_stack();
            let mut inbox = RingInbox(inbound);
            let mut buf = InboxBuffers::default();
            #[cfg(feature = "fault-injection")]
            let inject = super::fault_injection::FaultPlan::from_env();
            #[cfg(feature = "fault-injection")]
            let before_each = || inject.panic_if_due(HealthSource::SolverThread, monotonic_now_ns());
            #[cfg(not(feature = "fault-injection"))]
            let before_each = || {};
            let _ = ready_tx.send(placement);
            alloc_count::mark_rt_thread(true);
            stage.serve(&mut inbox, &mut buf, &MonotonicClock, before_each);
            alloc_count::mark_rt_thread(false);
        })
        .map_err(|_| StartError::Thread { thread: "solver" })?;
    match ready_rx.recv() {
        Ok(placement) => Ok((thread, placement)),
        Err(_) => Err(StartError::ThreadStartup { thread: "solver" }),
    }
}

/// The motor thread; returns the samples it had to drop.
fn spawn_motor<D: PlateDriver + Send + 'static>(
    params: &CoreParams,
    mut motor: MotorLoop<D>,
    shared: Arc<CoreShared>,
) -> Result<(JoinHandle<u64>, ThreadPlacement), StartError> {
    let (ready_tx, ready_rx) = mpsc::channel::<ThreadPlacement>();
    let (rt, period) = (params.rt, params.tick_ns());
    let thread = std::thread::Builder::new()
        .name("upm-motor".into())
        .stack_size(RT_STACK_BYTES)
        .spawn(move || {
            let _guard = CoreThread::enter(HealthSource::MotorThread, shared.clone());
            let placement = make_current_thread_realtime(rt.motor_priority, rt.motor_cpu);
            prefault_stack();
            let _ = ready_tx.send(placement);
            alloc_count::mark_rt_thread(true);
            motor.run(&MonotonicClock, period);
            alloc_count::mark_rt_thread(false);
            motor.dropped_samples()
        })
        .map_err(|_| StartError::Thread { thread: "motor" })?;
    match ready_rx.recv() {
        Ok(placement) => Ok((thread, placement)),
        Err(_) => Err(StartError::ThreadStartup { thread: "motor" }),
    }
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
    t.rejected_by_reason = shared.rejected_by_reason();
    let health = shared.health();
    t.health_source = health.source as u32;
    t.health_cause = health.cause as u32;
    t.health_detail = health.detail;
    t.driver = shared.driver.load();
}
