//! The rig as a non-RT client sees it (the line interface, the operator
//! page): the core's newest telemetry, the feed cell's newest status, its
//! running recipe and, if asked, the parts vision sees, read over iceoryx2
//! on a plain thread of the client's own (never an RT thread); the
//! operator's commands, the robot's picks and changeovers passed on to the
//! core; the client's own counters published for `upm status` where it
//! has them. The servers read a [`RigSnapshot`]; nothing they do makes the
//! core wait (iceoryx2 overwrites what the client has not read).

use std::collections::VecDeque;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, Sender, SyncSender, channel, sync_channel};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use ipc_types::ports::{Pub, Sub};
use ipc_types::wake_event::{WakeEvent, WakeNotifier};
use ipc_types::{
    CoreCommand, CoreState, FeedStatus, LineStatus, MAX_PICK_POSES, PartStates, PickCommand, RecipeCommand,
    RejectedKind, Rejection, RigInfo, Telemetry, ValidationLimits, monotonic_now_ns, service_names,
};
use upm_recipe::Recipe;

use crate::client_counters::ClientCounters;

/// The core is taken as gone when its telemetry is older than this.
const TELEMETRY_STALE: Duration = Duration::from_secs(2);
/// Parts per minute are counted over this window of the feed's own clock.
const RATE_WINDOW_S: f64 = 300.0;
/// How often the view thread looks for new messages.
const POLL: Duration = Duration::from_millis(5);
/// How often a client publishes its counters.
const STATUS_PERIOD: Duration = Duration::from_millis(200);
/// How long a changeover waits for the core's answer.
const CHANGEOVER_WAIT: Duration = Duration::from_millis(1500);

/// One pick pose as a robot reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseView {
    pub ready: bool,
    pub class: i32,
    /// The part lying at the pose; 0: none.
    pub part_id: u32,
    /// m, m, rad.
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

/// What the servers show: the newest of everything.
#[derive(Debug, Clone, PartialEq)]
pub struct RigSnapshot {
    pub state: CoreState,
    pub health: String,
    /// The running recipe's name, and its file (as the core announced it;
    /// empty before it did, or without a cell).
    pub recipe: String,
    pub recipe_path: String,
    /// Why the last `LoadRecipe` was refused; empty after one that worked.
    pub recipe_error: String,
    /// The plate's half extent (m), from the core's `RigInfo`.
    pub plate_half_extent: Option<[f64; 2]>,
    pub picked: u64,
    pub lost: u64,
    /// Picks per minute over the last five minutes of the cell's clock.
    pub parts_per_minute: f64,
    pub poses: Vec<PoseView>,
    /// Per pose, the part last passed on as picked: until the cell's
    /// status shows another part there, that pose is not ready (a status
    /// written before the cell took the pick may still arrive).
    pub sent: [u32; MAX_PICK_POSES],
    /// Messages received and refused (invalid) so far.
    pub telemetry_seen: u64,
    pub feed_seen: u64,
    pub invalid_messages: u64,
    /// The newest telemetry and feed status whole, as received.
    pub telemetry: Option<Telemetry>,
    pub feed: Option<FeedStatus>,
    /// The newest part states ([`ViewOptions::part_states`] only); shared,
    /// so a snapshot stays cheap to copy.
    pub parts: Option<Arc<PartStates>>,
}

impl RigSnapshot {
    fn new() -> Self {
        Self {
            state: CoreState::Idle,
            health: "no core yet".into(),
            recipe: String::new(),
            recipe_path: String::new(),
            recipe_error: String::new(),
            plate_half_extent: None,
            picked: 0,
            lost: 0,
            parts_per_minute: 0.0,
            poses: Vec::new(),
            sent: [0; MAX_PICK_POSES],
            telemetry_seen: 0,
            feed_seen: 0,
            invalid_messages: 0,
            telemetry: None,
            feed: None,
            parts: None,
        }
    }
}

/// What the servers ask of the rig.
#[derive(Debug, Clone)]
enum Ask {
    /// A `CoreCommand` code.
    Core(u32),
    /// The robot took `part_id` from `pose`.
    Pick { pose: u32, part_id: u32 },
    /// Switch to the recipe at this absolute path (checked).
    Recipe(String),
}

/// An order for the view thread, and where its outcome goes.
type Order = (Ask, SyncSender<Result<(), String>>);

/// Why a robot's pick was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PickRefusal {
    /// No such pose in the cell.
    OutOfRange,
    /// No part is ready at that pose.
    NotReady,
    /// The rig's own simulated robot picks: no one else may.
    BuiltinRobot,
    /// The view could not pass it on.
    Failed(String),
}

/// What a client asks of its view.
#[derive(Debug, Clone, Copy)]
pub struct ViewOptions {
    /// The view's iceoryx2 node name (`upm-line`, `upm-hmi`).
    pub node_name: &'static str,
    /// Also read the parts vision sees (`upm/part_states`), for a client
    /// that draws them.
    pub part_states: bool,
    /// Once the core's telemetry names it, move every thread of this
    /// process off the CPU the core's motor thread is pinned to.
    pub keep_off_motor_cpu: bool,
}

/// The running view; dropping it stops its thread.
pub struct RigView {
    snapshot: Arc<Mutex<RigSnapshot>>,
    counters: Arc<dyn ClientCounters>,
    orders: Mutex<Sender<Order>>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl std::fmt::Debug for RigView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RigView").finish_non_exhaustive()
    }
}

impl RigView {
    /// Watch the rig on `prefix`; `counters` count what the view passes
    /// on, and are published as `LineStatus` where they say so.
    pub fn start(
        prefix: &str,
        options: ViewOptions,
        counters: Arc<dyn ClientCounters>,
    ) -> anyhow::Result<Self> {
        let snapshot = Arc::new(Mutex::new(RigSnapshot::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let (tx, rx) = channel();
        let (snap, halt, prefix, count) =
            (snapshot.clone(), stop.clone(), prefix.to_owned(), counters.clone());
        // iceoryx2's ports stay on the thread that opened them.
        let (opened, outcome) = sync_channel(1);
        let thread =
            std::thread::Builder::new().name(format!("{}-view", options.node_name)).spawn(move || {
                match Ports::open(&prefix, &options, count.publishes_line_status()) {
                    Ok(ports) => {
                        let _ = opened.send(Ok(()));
                        view_loop(ports, &options, &snap, &rx, &halt, count.as_ref());
                    }
                    Err(e) => {
                        let _ = opened.send(Err(e));
                    }
                }
            })?;
        outcome.recv().map_err(|_| anyhow::anyhow!("the rig's view thread died at start"))??;
        Ok(Self { snapshot, counters, orders: Mutex::new(tx), stop, thread: Some(thread) })
    }

    /// The newest snapshot.
    pub fn snapshot(&self) -> RigSnapshot {
        lock(&self.snapshot).clone()
    }

    /// Send `command` (`CoreCommand::START`, `STOP`, `RESUME`) to the core.
    pub fn command(&self, command: u32) -> Result<(), String> {
        self.ask(Ask::Core(command), Duration::from_secs(1))
    }

    /// The robot took the part ready at `pose`: checked against the
    /// newest status, then passed to the cell (`PickCommand`). The pose
    /// reads not ready until the cell's next status.
    pub fn picked(&self, pose: u32, builtin_robot: bool) -> Result<(), PickRefusal> {
        let part_id = {
            let mut snap = lock(&self.snapshot);
            let p = snap.poses.get_mut(pose as usize).ok_or(PickRefusal::OutOfRange)?;
            if builtin_robot {
                return Err(PickRefusal::BuiltinRobot);
            }
            if !p.ready || p.part_id == 0 {
                return Err(PickRefusal::NotReady);
            }
            p.ready = false;
            let part_id = p.part_id;
            snap.sent[pose as usize] = part_id;
            part_id
        };
        self.ask(Ask::Pick { pose, part_id }, Duration::from_secs(1)).map_err(PickRefusal::Failed)
    }

    /// Switch the cell to recipe `name`: a name of `recipes_dir`
    /// (`NAME.toml` there) or a path. Checked here against the plate and
    /// the running recipe, then by the core; Ok once the core runs it,
    /// with its file. The refusal is one line; the running recipe stays.
    pub fn load_recipe(&self, name: &str, recipes_dir: &Path) -> Result<String, String> {
        let outcome = self.check_recipe(name, recipes_dir).and_then(|path| {
            self.ask(Ask::Recipe(path.clone()), CHANGEOVER_WAIT + Duration::from_millis(500)).map(|()| path)
        });
        self.counters.recipe_outcome(outcome.is_ok());
        lock(&self.snapshot).recipe_error = outcome.as_ref().err().cloned().unwrap_or_default();
        outcome
    }

    /// The absolute path of recipe `name`, if the running cell may switch to it.
    fn check_recipe(&self, name: &str, recipes_dir: &Path) -> Result<String, String> {
        let (running, plate) = {
            let snap = lock(&self.snapshot);
            (snap.recipe_path.clone(), snap.plate_half_extent)
        };
        if running.is_empty() {
            return Err("the rig runs no feed cell (no recipe announced on upm/recipe/active)".into());
        }
        let plate = plate.ok_or("the core has not described the rig yet (upm/rig_info)")?;
        if name.trim().is_empty() {
            return Err("no recipe named".into());
        }
        let file = if name.contains('/') || name.ends_with(".toml") {
            Path::new(name).to_path_buf()
        } else {
            recipes_dir.join(format!("{name}.toml"))
        };
        let path =
            std::fs::canonicalize(&file).map_err(|e| format!("recipe {name:?}: {}: {e}", file.display()))?;
        let next = Recipe::load(&path, plate).map_err(|e| e.to_string())?;
        let now = Recipe::load(Path::new(&running), plate).map_err(|e| format!("the running recipe: {e}"))?;
        now.check_changeover(&next).map_err(|e| format!("{}: {e}", path.display()))?;
        let path = path.to_str().ok_or_else(|| format!("{}: not UTF-8", path.display()))?.to_owned();
        RecipeCommand::new(&path, 0, 0).map_err(|e| e.to_string())?;
        Ok(path)
    }

    fn ask(&self, ask: Ask, wait: Duration) -> Result<(), String> {
        let (done, outcome) = sync_channel(1);
        lock(&self.orders).send((ask, done)).map_err(|_| "the rig's view thread has stopped".to_owned())?;
        outcome.recv_timeout(wait).map_err(|_| "the rig's view thread did not answer".to_owned())?
    }
}

impl Drop for RigView {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

struct Ports {
    telemetry: Sub<Telemetry>,
    feed: Sub<FeedStatus>,
    command: Pub<CoreCommand>,
    pick: Pub<PickCommand>,
    recipe: Pub<RecipeCommand>,
    recipe_active: Sub<RecipeCommand>,
    rejections: Sub<Rejection>,
    rig_info: Sub<RigInfo>,
    parts: Option<Sub<PartStates>>,
    /// Only for a client that publishes its counters (the line).
    status: Option<Pub<LineStatus>>,
    notifier: WakeNotifier,
    _node: Node<ipc::Service>,
}

impl Ports {
    fn open(prefix: &str, options: &ViewOptions, publishes_status: bool) -> anyhow::Result<Self> {
        let node =
            ipc_types::rig_node::rig_node(prefix, Some(options.node_name), SignalHandlingMode::Disabled)?;
        Ok(Self {
            telemetry: ipc_types::ports::subscriber(&node, service_names::TELEMETRY)?,
            feed: ipc_types::ports::subscriber(&node, service_names::FEED)?,
            command: ipc_types::ports::publisher(&node, service_names::CORE_COMMAND)?,
            pick: ipc_types::ports::publisher(&node, service_names::PICK)?,
            recipe: ipc_types::ports::publisher(&node, service_names::RECIPE)?,
            recipe_active: ipc_types::ports::subscriber(&node, service_names::RECIPE_ACTIVE)?,
            rejections: ipc_types::ports::subscriber(&node, service_names::REJECTION)?,
            rig_info: ipc_types::ports::subscriber(&node, service_names::RIG_INFO)?,
            parts: match options.part_states {
                true => Some(ipc_types::ports::subscriber(&node, service_names::PART_STATES)?),
                false => None,
            },
            status: match publishes_status {
                true => Some(ipc_types::ports::publisher(&node, service_names::LINE)?),
                false => None,
            },
            notifier: WakeNotifier::new(&node, WakeEvent::Inbox)?,
            _node: node,
        })
    }
}

/// (cell time s, picked) samples for the rate.
#[derive(Debug, Default)]
struct Rate {
    samples: VecDeque<(f64, u64)>,
}

impl Rate {
    fn add(&mut self, t: f64, picked: u64) -> f64 {
        if self.samples.back().is_some_and(|&(last, _)| t < last) {
            self.samples.clear(); // a new cell: its clock starts again
        }
        self.samples.push_back((t, picked));
        while self.samples.front().is_some_and(|&(t0, _)| t - t0 > RATE_WINDOW_S) {
            self.samples.pop_front();
        }
        match (self.samples.front(), self.samples.back()) {
            (Some(&(t0, p0)), Some(&(t1, p1))) if t1 - t0 >= 10.0 => {
                p1.saturating_sub(p0) as f64 * 60.0 / (t1 - t0)
            }
            _ => 0.0,
        }
    }
}

/// A changeover sent, waiting for the core to announce it or refuse it.
struct Changeover {
    seq: u64,
    done: SyncSender<Result<(), String>>,
    deadline: Instant,
}

fn view_loop(
    mut ports: Ports,
    options: &ViewOptions,
    snapshot: &Mutex<RigSnapshot>,
    orders: &Receiver<Order>,
    stop: &AtomicBool,
    counters: &dyn ClientCounters,
) {
    // One sequence per service: a recorder counts a gap as lost messages.
    let (mut core_seq, mut pick_seq, mut recipe_seq, mut status_seq) = (0, 0, 0, 0);
    let mut rate = Rate::default();
    let mut last_telemetry: Option<Instant> = None;
    let mut changeover: Option<Changeover> = None;
    let mut status = LineStatus::new();
    status.line_pid = std::process::id();
    let mut next_status = Instant::now();
    // The core whose motor CPU this process was kept off.
    let mut placed_for_core = 0;
    while !stop.load(Ordering::Relaxed) {
        while let Ok((ask, done)) = orders.try_recv() {
            let now = monotonic_now_ns();
            let sent = match ask {
                Ask::Core(command) => {
                    core_seq += 1;
                    ports.command.send_copy(CoreCommand::new(command, core_seq, now))
                }
                Ask::Pick { pose, part_id } => {
                    pick_seq += 1;
                    let sent = ports.pick.send_copy(PickCommand::new(pose, part_id, pick_seq, now));
                    if sent.is_ok() {
                        counters.pick_sent();
                    }
                    sent
                }
                Ask::Recipe(path) => {
                    if changeover.is_some() {
                        let _ = done.send(Err("another changeover is under way".into()));
                        continue;
                    }
                    let command = match RecipeCommand::new(&path, recipe_seq + 1, now) {
                        Ok(c) => c,
                        Err(e) => {
                            let _ = done.send(Err(e.to_string()));
                            continue;
                        }
                    };
                    recipe_seq += 1;
                    match ports.recipe.send_copy(command) {
                        Ok(_) => {
                            ports.notifier.notify();
                            let deadline = Instant::now() + CHANGEOVER_WAIT;
                            changeover = Some(Changeover { seq: recipe_seq, done, deadline });
                            continue;
                        }
                        Err(e) => Err(e),
                    }
                }
            };
            let sent =
                sent.map(|_| ports.notifier.notify()).map_err(|e| format!("sending to the core: {e:?}"));
            let _ = done.send(sent);
        }
        let answer = watch_changeover(&ports, snapshot, changeover.as_ref().map(|c| c.seq));
        if let Some(c) = changeover.take_if(|c| answer.is_some() || Instant::now() >= c.deadline) {
            let _ =
                c.done.send(answer.unwrap_or_else(|| Err("the core did not answer the changeover".into())));
        }
        if let Some(publisher) = ports.status.as_ref().filter(|_| Instant::now() >= next_status) {
            next_status += STATUS_PERIOD;
            status_seq += 1;
            (status.seq, status.stamp_ns) = (status_seq, monotonic_now_ns());
            counters.write_line_status(&mut status);
            let _ = publisher.send_copy(status);
        }
        // Messages are checked whole; where a part may lie is the core's business.
        let limits = ValidationLimits::new([f64::INFINITY; 2], monotonic_now_ns());
        let mut telemetry = None;
        let mut feed = None;
        let mut invalid = 0;
        while let Ok(Some(s)) = ports.telemetry.receive() {
            match s.payload().validate(&limits) {
                Ok(()) => telemetry = Some(*s.payload()),
                Err(_) => invalid += 1,
            }
        }
        while let Ok(Some(s)) = ports.feed.receive() {
            match s.payload().validate(&limits) {
                Ok(()) => feed = Some(*s.payload()),
                Err(_) => invalid += 1,
            }
        }
        let mut parts = None;
        while let Some(Ok(Some(s))) = ports.parts.as_ref().map(|p| p.receive()) {
            match s.payload().validate(&limits) {
                Ok(()) => parts = Some(Arc::new(*s.payload())),
                Err(_) => invalid += 1,
            }
        }
        if let Some(t) =
            telemetry.as_ref().filter(|t| options.keep_off_motor_cpu && t.core_pid != placed_for_core)
        {
            placed_for_core = t.core_pid;
            if let Some(cpu) = crate::motor_cpu::motor_cpu(t.core_pid) {
                crate::motor_cpu::keep_process_off(cpu);
            }
        }
        {
            let mut snap = lock(snapshot);
            snap.invalid_messages += invalid;
            if parts.is_some() {
                snap.parts = parts;
            }
            if let Some(t) = &telemetry {
                last_telemetry = Some(Instant::now());
                snap.telemetry_seen += 1;
                snap.telemetry = Some(*t);
                snap.state = t.core_state().unwrap_or(CoreState::Fault);
                snap.health = match t.health() {
                    Some((source, cause)) if t.health_detail_str().is_empty() => format!("{source}: {cause}"),
                    Some((source, cause)) => format!("{source}: {cause}: {}", t.health_detail_str()),
                    None => "unknown health code".into(),
                };
            } else if last_telemetry.is_some_and(|at| at.elapsed() > TELEMETRY_STALE) {
                snap.state = CoreState::Fault;
                snap.health = format!("no telemetry from the core for over {} s", TELEMETRY_STALE.as_secs());
            }
            if let Some(f) = &feed {
                snap.feed_seen += 1;
                snap.feed = Some(*f);
                snap.picked = f.picked;
                snap.lost = f.lost;
                snap.parts_per_minute = rate.add(f.time_s, f.picked);
                snap.poses.clear();
                let n = (f.count as usize).min(f.poses.len());
                let sent = snap.sent;
                snap.poses.extend(f.poses[..n].iter().zip(sent).map(|(p, sent)| PoseView {
                    ready: p.ready != 0 && p.part_id != sent,
                    class: i32::try_from(p.class).unwrap_or(i32::MAX),
                    part_id: p.part_id,
                    x: p.x,
                    y: p.y,
                    theta: p.theta,
                }));
            }
        }
        std::thread::sleep(POLL);
    }
}

/// The running recipe and the plate, as the core announces them; the
/// core's answer to changeover `pending`, if it came.
fn watch_changeover(
    ports: &Ports,
    snapshot: &Mutex<RigSnapshot>,
    pending: Option<u64>,
) -> Option<Result<(), String>> {
    let limits = ValidationLimits::new([f64::INFINITY; 2], monotonic_now_ns());
    let mut answer = None;
    while let Ok(Some(s)) = ports.rig_info.receive() {
        if s.payload().validate(&limits).is_ok() {
            lock(snapshot).plate_half_extent = Some(s.payload().plate_half_extent);
        }
    }
    while let Ok(Some(s)) = ports.recipe_active.receive() {
        let Ok(path) = s.payload().path() else { continue };
        let mut snap = lock(snapshot);
        snap.recipe_path = path.to_owned();
        snap.recipe = recipe_name(path);
        if pending == Some(s.payload().seq) {
            answer = Some(Ok(()));
        }
    }
    while let Ok(Some(s)) = ports.rejections.receive() {
        let r = s.payload();
        if pending == Some(r.seq) && r.kind() == Some(RejectedKind::RecipeCommand) {
            answer = Some(Err(format!("the core refused it: {}", r.detail_str())));
        }
    }
    answer
}

/// What `Rig.Recipe` shows: the recipe file's name without `.toml`.
fn recipe_name(path: &str) -> String {
    Path::new(path).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_counts_picks_over_its_window_and_restarts_with_the_cell() {
        let mut r = Rate::default();
        assert_eq!(r.add(0.0, 0), 0.0);
        assert_eq!(r.add(5.0, 1), 0.0, "under 10 s is no rate");
        assert!((r.add(60.0, 10) - 10.0).abs() < 1e-9);
        // 400 s: the window holds 100..400 s only.
        for t in (61..=400).step_by(1) {
            r.add(f64::from(t), 10 + u64::from(t as u32 - 60) / 6);
        }
        let ppm = r.add(400.0, 66);
        assert!((ppm - 10.0).abs() < 0.5, "{ppm}");
        assert_eq!(r.add(1.0, 0), 0.0, "a cell whose clock went back starts over");
    }
}
