//! The flight recorder: every service of a rig, subscribed, into a
//! [`RigLog`]. It runs in a process of its own: if it falls behind,
//! iceoryx2 overwrites its oldest samples (the core never waits) and the
//! gap in each publisher's `seq` is counted into the file's metadata.

use std::collections::BTreeMap;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use iceoryx2::prelude::*;
use ipc_types::ports::{FrameSub, Sub, subscriber};
use ipc_types::{
    CoreCommand, ExplicitSchedule, FeedStatus, ForceRequest, LineStatus, PartStates, PickCommand,
    RecipeCommand, Rejection, RigInfo, Schedule, Telemetry, monotonic_now_ns, service_names,
};

use crate::rig_log::{LogOptions, RigLog};
use crate::seq_gaps::SeqGaps;

/// What to record, where to.
#[derive(Debug, Clone, Default)]
pub struct RecorderOptions {
    pub prefix: String,
    pub log: LogOptions,
    /// Record camera frames' pixels (the header is always recorded).
    pub frame_pixels: bool,
    /// Keep at most this many simulator ground-truth messages a second (0:
    /// all). The truth is no input of the core; at the core's 1 kHz it
    /// would be most of the file.
    pub truth_hz: f64,
}

/// Every service of the rig, subscribed.
#[derive(Debug)]
struct Subscriptions {
    parts: Sub<PartStates>,
    request: Sub<ForceRequest>,
    explicit: Sub<ExplicitSchedule>,
    command: Sub<CoreCommand>,
    pick: Sub<PickCommand>,
    recipe: Sub<RecipeCommand>,
    recipe_active: Sub<RecipeCommand>,
    line: Sub<LineStatus>,
    schedule: Sub<Schedule>,
    telemetry: Sub<Telemetry>,
    rejection: Sub<Rejection>,
    rig_info: Sub<RigInfo>,
    feed: Sub<FeedStatus>,
    truth: Sub<PartStates>,
    frames: Option<FrameSub>,
}

/// A running recorder; [`Recorder::poll`] at least every few milliseconds
/// (or [`Recorder::run`]), then [`Recorder::finish`].
#[derive(Debug)]
pub struct Recorder {
    node: Node<ipc::Service>,
    subs: Subscriptions,
    log: RigLog,
    /// CLOCK_MONOTONIC and Unix time at start: log times are Unix ns.
    mono0: u64,
    unix0: u64,
    frame_pixels: bool,
    truth_period_ns: u64,
    last_truth_ns: u64,
    /// Ground truth left out by `truth_hz` (not lost: chosen).
    truth_thinned: u64,
    /// Gaps in `seq` per (service, publisher).
    gaps: BTreeMap<(&'static str, u128), SeqGaps>,
}

/// Services whose publishers number their messages one by one, so a gap
/// in `seq` is a loss. Not: a schedule's `seq` is its request's, a
/// rejection's the refused message's, the ground truth's the tick (the io
/// thread publishes the newest pose). A feed status is numbered by each
/// write of the cell, which the io thread publishes well within its period.
/// A pick is numbered by its robot, a recipe command by the line, like a
/// command by its sender; the line numbers its statuses one by one. Not:
/// the active recipe, whose `seq` is the accepted command's (0 at start).
const COUNTED_BY_SEQ: [&str; 10] = [
    service_names::PART_STATES,
    service_names::FORCE_REQUEST,
    service_names::EXPLICIT_SCHEDULE,
    service_names::CORE_COMMAND,
    service_names::PICK,
    service_names::RECIPE,
    service_names::LINE,
    service_names::TELEMETRY,
    service_names::FEED,
    service_names::CAMERA_FRAME,
];

impl Recorder {
    pub fn start(opts: &RecorderOptions) -> anyhow::Result<Self> {
        // Subscribed before the file exists: a launcher that waits for the
        // file knows nothing published after it is missed.
        let node =
            ipc_types::rig_node::rig_node(&opts.prefix, None, SignalHandlingMode::HandleTerminationRequests)?;
        let subs = Subscriptions {
            parts: subscriber(&node, service_names::PART_STATES)?,
            truth: subscriber(&node, service_names::SIM_GROUND_TRUTH)?,
            request: subscriber(&node, service_names::FORCE_REQUEST)?,
            explicit: subscriber(&node, service_names::EXPLICIT_SCHEDULE)?,
            command: subscriber(&node, service_names::CORE_COMMAND)?,
            // Only an external robot publishes here.
            pick: subscriber(&node, service_names::PICK)?,
            // Only the line process publishes these two; only a core
            // running a feed cell the active recipe.
            recipe: subscriber(&node, service_names::RECIPE)?,
            recipe_active: subscriber(&node, service_names::RECIPE_ACTIVE)?,
            line: subscriber(&node, service_names::LINE)?,
            schedule: subscriber(&node, service_names::SCHEDULE)?,
            telemetry: subscriber(&node, service_names::TELEMETRY)?,
            rejection: subscriber(&node, service_names::REJECTION)?,
            rig_info: subscriber(&node, service_names::RIG_INFO)?,
            // Only a core that runs a feed cell publishes here.
            feed: subscriber(&node, service_names::FEED)?,
            // Only a rig with a camera has the frame service.
            frames: ipc_types::ports::frame_subscriber(&node).ok(),
        };
        let mono0 = monotonic_now_ns();
        let unix0 = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_nanos() as u64);
        let mut log_opts = opts.log.clone();
        log_opts.info.insert("prefix".into(), opts.prefix.clone());
        log_opts.info.insert("monotonic_at_start_ns".into(), mono0.to_string());
        log_opts.info.insert("unix_at_start_ns".into(), unix0.to_string());
        log_opts.info.insert("frame_pixels".into(), opts.frame_pixels.to_string());
        log_opts.info.insert("truth_hz".into(), opts.truth_hz.to_string());
        let log = RigLog::open(&log_opts)?;
        let truth_period_ns =
            if opts.truth_hz > 0.0 && opts.truth_hz.is_finite() { (1e9 / opts.truth_hz) as u64 } else { 0 };
        Ok(Self {
            node,
            subs,
            log,
            mono0,
            unix0,
            frame_pixels: opts.frame_pixels,
            truth_period_ns,
            last_truth_ns: 0,
            truth_thinned: 0,
            gaps: BTreeMap::new(),
        })
    }

    /// The WebSocket server's port, if serving.
    pub fn port(&self) -> Option<u16> {
        self.log.port()
    }

    fn log_ns(&self) -> u64 {
        self.unix0 + monotonic_now_ns().saturating_sub(self.mono0)
    }

    /// Take everything that arrived; returns how many messages.
    pub fn poll(&mut self) -> anyhow::Result<u64> {
        let mut n = 0;
        macro_rules! drain {
            ($sub:ident, $service:expr) => {
                while let Some(s) =
                    self.subs.$sub.receive().map_err(|e| anyhow::anyhow!("{}: {e:?}", $service))?
                {
                    let m = *s.payload();
                    let at = self.log_ns();
                    self.gaps.entry(($service, s.header().publisher_id().value())).or_default().see(m.seq);
                    self.log.log($service, &m, &[], at);
                    n += 1;
                }
            };
        }
        drain!(parts, service_names::PART_STATES);
        drain!(request, service_names::FORCE_REQUEST);
        drain!(explicit, service_names::EXPLICIT_SCHEDULE);
        drain!(command, service_names::CORE_COMMAND);
        drain!(pick, service_names::PICK);
        drain!(recipe, service_names::RECIPE);
        drain!(recipe_active, service_names::RECIPE_ACTIVE);
        drain!(line, service_names::LINE);
        drain!(schedule, service_names::SCHEDULE);
        drain!(rejection, service_names::REJECTION);
        drain!(rig_info, service_names::RIG_INFO);
        drain!(feed, service_names::FEED);
        while let Some(s) = self.subs.truth.receive().map_err(|e| anyhow::anyhow!("ground truth: {e:?}"))? {
            let at = self.log_ns();
            if at >= self.last_truth_ns.saturating_add(self.truth_period_ns) {
                self.last_truth_ns = at;
                let m = *s.payload();
                self.log.log(service_names::SIM_GROUND_TRUTH, &m, &[], at);
                n += 1;
            } else {
                self.truth_thinned += 1;
            }
        }
        drain!(telemetry, service_names::TELEMETRY);
        if let Some(frames) = &self.subs.frames {
            while let Some(s) = frames.receive().map_err(|e| anyhow::anyhow!("camera frame: {e:?}"))? {
                let h = *s.user_header();
                let at = self.log_ns();
                let service = service_names::CAMERA_FRAME;
                self.gaps.entry((service, s.header().publisher_id().value())).or_default().see(h.seq);
                let pixels: &[u8] = if self.frame_pixels { s.payload() } else { &[] };
                self.log.log(service, &h, pixels, at);
                n += 1;
            }
        }
        let now = self.log_ns();
        self.log.view(now);
        if self.log.segment_due(now) {
            let _ = self.counts();
            self.log.next_segment(now)?;
        }
        Ok(n)
    }

    /// Poll until SIGINT/SIGTERM or until `stop` returns true (checked
    /// every millisecond).
    pub fn run(&mut self, mut stop: impl FnMut() -> bool) -> anyhow::Result<()> {
        loop {
            self.poll()?;
            if stop() || self.node.wait(Duration::from_millis(1)).is_err() {
                return Ok(());
            }
        }
    }

    /// Messages received and lost per topic so far (None: cannot tell).
    pub fn counts(&mut self) -> BTreeMap<String, (u64, Option<u64>)> {
        for service in service_names::ALL {
            let lost = COUNTED_BY_SEQ.contains(&service).then(|| {
                self.gaps.range((service, 0)..=(service, u128::MAX)).map(|(_, g)| g.lost).sum::<u64>()
            });
            self.log.set_lost(service, lost);
        }
        self.log.counts()
    }

    /// Take what is left, then close the log (see [`RigLog::finish`]).
    pub fn finish(mut self) -> anyhow::Result<BTreeMap<String, (u64, Option<u64>)>> {
        self.poll()?;
        let _ = self.counts();
        let thinned = self.truth_thinned.to_string();
        self.log.note(&format!("thinned {}", service_names::SIM_GROUND_TRUTH), thinned);
        self.log.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A feed status crosses shared memory into the log, and a gap in its
    /// `seq` is counted as lost.
    #[test]
    fn feed_status_is_recorded_and_its_gaps_counted() -> anyhow::Result<()> {
        let prefix = format!("upm_rec_feed_{}_", std::process::id());
        let mut rec = Recorder::start(&RecorderOptions { prefix: prefix.clone(), ..Default::default() })?;
        let node = ipc_types::rig_node::rig_node(&prefix, None, SignalHandlingMode::Disabled)?;
        let feed = ipc_types::ports::publisher::<FeedStatus>(&node, service_names::FEED)?;
        let mut m = FeedStatus::new();
        for seq in [1, 2, 4] {
            m.seq = seq;
            m.stamp_ns = monotonic_now_ns();
            feed.send_copy(m).map_err(|e| anyhow::anyhow!("{e:?}"))?;
        }
        let mut received = 0;
        for _ in 0..1000 {
            received += rec.poll()?;
            if received >= 3 {
                break;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let counts = rec.finish()?;
        drop(feed);
        drop(node);
        ipc_types::rig_node::remove_prefix_segment(&prefix);
        assert_eq!(counts.get(service_names::FEED), Some(&(3, Some(1))), "{counts:?}");
        Ok(())
    }

    /// A robot's picks cross shared memory into the log, and a gap in
    /// their `seq` is counted as lost.
    #[test]
    fn picks_are_recorded_and_their_gaps_counted() -> anyhow::Result<()> {
        let prefix = format!("upm_rec_pick_{}_", std::process::id());
        let mut rec = Recorder::start(&RecorderOptions { prefix: prefix.clone(), ..Default::default() })?;
        let node = ipc_types::rig_node::rig_node(&prefix, None, SignalHandlingMode::Disabled)?;
        let picks = ipc_types::ports::publisher::<PickCommand>(&node, service_names::PICK)?;
        for seq in [1, 2, 5] {
            let m = PickCommand::new(seq as u32 % 3, 10 + seq as u32, seq, monotonic_now_ns());
            picks.send_copy(m).map_err(|e| anyhow::anyhow!("{e:?}"))?;
        }
        let mut received = 0;
        for _ in 0..1000 {
            received += rec.poll()?;
            if received >= 3 {
                break;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let counts = rec.finish()?;
        drop(picks);
        drop(node);
        ipc_types::rig_node::remove_prefix_segment(&prefix);
        assert_eq!(counts.get(service_names::PICK), Some(&(3, Some(2))), "{counts:?}");
        Ok(())
    }

    /// The line's recipe commands and statuses cross shared memory into
    /// the log with their gaps counted; the core's active recipe is
    /// recorded, its losses unknown (its `seq` is the command's).
    #[test]
    fn recipes_and_line_statuses_are_recorded_and_their_gaps_counted() -> anyhow::Result<()> {
        let prefix = format!("upm_rec_line_{}_", std::process::id());
        let mut rec = Recorder::start(&RecorderOptions { prefix: prefix.clone(), ..Default::default() })?;
        let node = ipc_types::rig_node::rig_node(&prefix, None, SignalHandlingMode::Disabled)?;
        let recipes = ipc_types::ports::publisher::<RecipeCommand>(&node, service_names::RECIPE)?;
        let active = ipc_types::ports::publisher::<RecipeCommand>(&node, service_names::RECIPE_ACTIVE)?;
        let statuses = ipc_types::ports::publisher::<LineStatus>(&node, service_names::LINE)?;
        let send_err = |e| anyhow::anyhow!("{e:?}");
        for seq in [1, 2, 4] {
            let m = RecipeCommand::new(&format!("/srv/recipes/{seq}.toml"), seq, monotonic_now_ns())?;
            recipes.send_copy(m).map_err(send_err)?;
        }
        for seq in [0, 2] {
            let m = RecipeCommand::new("/srv/recipes/2.toml", seq, monotonic_now_ns())?;
            active.send_copy(m).map_err(send_err)?;
        }
        let mut m = LineStatus::new();
        for seq in [1, 2, 3, 6] {
            (m.seq, m.stamp_ns, m.login_failures) = (seq, monotonic_now_ns(), seq);
            statuses.send_copy(m).map_err(send_err)?;
        }
        let mut received = 0;
        for _ in 0..1000 {
            received += rec.poll()?;
            if received >= 9 {
                break;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let counts = rec.finish()?;
        drop((recipes, active, statuses));
        drop(node);
        ipc_types::rig_node::remove_prefix_segment(&prefix);
        assert_eq!(counts.get(service_names::RECIPE), Some(&(3, Some(1))), "{counts:?}");
        assert_eq!(counts.get(service_names::RECIPE_ACTIVE), Some(&(2, None)), "{counts:?}");
        assert_eq!(counts.get(service_names::LINE), Some(&(4, Some(2))), "{counts:?}");
        Ok(())
    }
}
