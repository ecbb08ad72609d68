//! The rig as the line sees it: the core's newest telemetry and the feed
//! cell's newest status, read over iceoryx2 on a plain thread of the
//! line's own (never an RT thread), and the operator's commands passed on
//! to the core. The servers read a [`RigSnapshot`]; nothing they do makes
//! the core wait (iceoryx2 overwrites what the line has not read).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, Sender, SyncSender, channel, sync_channel};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use ipc_types::ports::{Pub, Sub};
use ipc_types::wake_event::{WakeEvent, WakeNotifier};
use ipc_types::{
    CoreCommand, CoreState, FeedStatus, MAX_PICK_POSES, PickCommand, Telemetry, ValidationLimits,
    monotonic_now_ns, service_names,
};

/// The core is taken as gone when its telemetry is older than this.
const TELEMETRY_STALE: Duration = Duration::from_secs(2);
/// Parts per minute are counted over this window of the feed's own clock.
const RATE_WINDOW_S: f64 = 300.0;
/// How often the view thread looks for new messages.
const POLL: Duration = Duration::from_millis(5);

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
    pub recipe: String,
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
}

impl RigSnapshot {
    fn new(recipe: &str) -> Self {
        Self {
            state: CoreState::Idle,
            health: "no core yet".into(),
            recipe: recipe.into(),
            picked: 0,
            lost: 0,
            parts_per_minute: 0.0,
            poses: Vec::new(),
            sent: [0; MAX_PICK_POSES],
            telemetry_seen: 0,
            feed_seen: 0,
            invalid_messages: 0,
        }
    }
}

/// What the servers ask of the rig.
#[derive(Debug, Clone, Copy)]
enum Ask {
    /// A `CoreCommand` code.
    Core(u32),
    /// The robot took `part_id` from `pose`.
    Pick { pose: u32, part_id: u32 },
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
    /// The line could not pass it on.
    Failed(String),
}

/// The running view; dropping it stops its thread.
#[derive(Debug)]
pub struct RigView {
    snapshot: Arc<Mutex<RigSnapshot>>,
    orders: Mutex<Sender<Order>>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl RigView {
    /// Watch the rig on `prefix`; `recipe` is what `Rig.Recipe` shows.
    pub fn start(prefix: &str, recipe: &str) -> anyhow::Result<Self> {
        let snapshot = Arc::new(Mutex::new(RigSnapshot::new(recipe)));
        let stop = Arc::new(AtomicBool::new(false));
        let (tx, rx) = channel();
        let (snap, halt, prefix) = (snapshot.clone(), stop.clone(), prefix.to_owned());
        // iceoryx2's ports stay on the thread that opened them.
        let (opened, outcome) = sync_channel(1);
        let thread =
            std::thread::Builder::new().name("upm-line-view".into()).spawn(move || {
                match Ports::open(&prefix) {
                    Ok(ports) => {
                        let _ = opened.send(Ok(()));
                        view_loop(ports, &snap, &rx, &halt);
                    }
                    Err(e) => {
                        let _ = opened.send(Err(e));
                    }
                }
            })?;
        outcome.recv().map_err(|_| anyhow::anyhow!("the line's view thread died at start"))??;
        Ok(Self { snapshot, orders: Mutex::new(tx), stop, thread: Some(thread) })
    }

    /// The newest snapshot.
    pub fn snapshot(&self) -> RigSnapshot {
        lock(&self.snapshot).clone()
    }

    /// Send `command` (`CoreCommand::START`, `STOP`, `RESUME`) to the core.
    pub fn command(&self, command: u32) -> Result<(), String> {
        self.ask(Ask::Core(command))
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
        self.ask(Ask::Pick { pose, part_id }).map_err(PickRefusal::Failed)
    }

    fn ask(&self, ask: Ask) -> Result<(), String> {
        let (done, outcome) = sync_channel(1);
        lock(&self.orders).send((ask, done)).map_err(|_| "the line's view thread has stopped".to_owned())?;
        outcome
            .recv_timeout(Duration::from_secs(1))
            .map_err(|_| "the line's view thread did not answer".to_owned())?
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
    notifier: WakeNotifier,
    _node: Node<ipc::Service>,
}

impl Ports {
    fn open(prefix: &str) -> anyhow::Result<Self> {
        let node = ipc_types::rig_node::rig_node(prefix, Some("upm-line"), SignalHandlingMode::Disabled)?;
        Ok(Self {
            telemetry: ipc_types::ports::subscriber(&node, service_names::TELEMETRY)?,
            feed: ipc_types::ports::subscriber(&node, service_names::FEED)?,
            command: ipc_types::ports::publisher(&node, service_names::CORE_COMMAND)?,
            pick: ipc_types::ports::publisher(&node, service_names::PICK)?,
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

fn view_loop(mut ports: Ports, snapshot: &Mutex<RigSnapshot>, orders: &Receiver<Order>, stop: &AtomicBool) {
    let mut seq = 0;
    let mut rate = Rate::default();
    let mut last_telemetry: Option<Instant> = None;
    while !stop.load(Ordering::Relaxed) {
        while let Ok((ask, done)) = orders.try_recv() {
            seq += 1;
            let now = monotonic_now_ns();
            let sent = match ask {
                Ask::Core(command) => ports.command.send_copy(CoreCommand::new(command, seq, now)),
                Ask::Pick { pose, part_id } => {
                    ports.pick.send_copy(PickCommand::new(pose, part_id, seq, now))
                }
            };
            let sent =
                sent.map(|_| ports.notifier.notify()).map_err(|e| format!("sending to the core: {e:?}"));
            let _ = done.send(sent);
        }
        // The line checks messages whole; where a part may lie is the core's business.
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
        {
            let mut snap = lock(snapshot);
            snap.invalid_messages += invalid;
            if let Some(t) = &telemetry {
                last_telemetry = Some(Instant::now());
                snap.telemetry_seen += 1;
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
