//! The closed loop in one process on a hand-stepped clock: the same core
//! (`Lockstep`), simulator, planner and message types as `upm run`, with
//! the camera `upm run` has: vision's ground-truth test double (seeded
//! noise, dropped frames and latency from `[vision]`, then the tracker,
//! [`TruthSight`]), or the rendered camera and vision's image pipeline
//! ([`RenderedSight`]). Much faster than real time and bit-identical for a
//! seed: used by the tests and `upm bench sort`.

use ipc_types::{ForceRequest, PartStates};
use rt_core::QueueInbox;
use rt_core::lockstep::Lockstep;

use crate::config::{Config, DriverChoice, SimParts};
use crate::launcher::{CameraChoice, Trails};
use crate::rendered_sight::RenderedSight;
use crate::truth_sight::TruthSight;
use upm_core::plate_driver::SimulatedPlant;
use upm_planner::Planner;

/// What a lock-step run leaves behind.
#[derive(Debug)]
pub struct LoopResult {
    pub trails: Trails,
    pub hold_events: u64,
    pub rejected_requests: u64,
    pub saturated_schedules: usize,
    pub schedules: usize,
    /// The largest of the per-center |k| bounds the core's solver used.
    pub k_max: f64,
    /// Mean residual ‖A·K − b‖ over the schedules (N; curl rows in N/m).
    pub mean_residual: f64,
    /// Rank and condition of the first schedule.
    pub first_rank_condition: (u32, f64),
    /// Through rendered frames: parts detected, blobs merged, frames skipped.
    pub sight: Option<(u64, u64, u64)>,
    /// What the feed cell did, if the simulator plays one.
    pub feed: Option<crate::feed_metrics::FeedOutcome>,
}

/// Run `seconds` of simulated time, the planner seeing the simulator's
/// truth through vision's test double.
pub fn run(config: &Config, planner: &mut dyn Planner, seconds: f64) -> anyhow::Result<LoopResult> {
    run_seeing(config, planner, seconds, CameraChoice::Truth)
}

/// Run `seconds` of simulated time, the planner seeing what `camera` shows,
/// on the plate `[driver]` names (the simulator, or the EtherCAT driver
/// over the simulated chain).
pub fn run_seeing(
    config: &Config,
    planner: &mut dyn Planner,
    seconds: f64,
    camera: CameraChoice,
) -> anyhow::Result<LoopResult> {
    run_client(config, &mut PlannerClient(planner), seconds, camera)
}

/// What answers each frame the core gets, in lock-step: a planner's force
/// request, or explicit schedules (the plate calibration).
pub trait LoopClient {
    /// Push the answer to `seen` (at `time` s since the first frame, the
    /// core's clock at `now_ns`) into `inbox`. False: the client is done
    /// and the run stops.
    fn answer(&mut self, seen: &PartStates, time: f64, now_ns: u64, inbox: &mut QueueInbox) -> bool;
}

/// A planner as the planner process runs it: its request follows the
/// frame at once.
struct PlannerClient<'a>(&'a mut dyn Planner);

impl LoopClient for PlannerClient<'_> {
    fn answer(&mut self, seen: &PartStates, time: f64, now_ns: u64, inbox: &mut QueueInbox) -> bool {
        let mut request = ForceRequest::new();
        if self.0.plan(seen, time, &mut request) {
            request.seq = seen.seq;
            request.stamp_ns = now_ns;
            request.deadline_ns = now_ns + upm_planner::run::REQUEST_LIFETIME_NS;
            inbox.push_request(&request);
        }
        true
    }
}

/// [`run_seeing`] with any client, until `seconds` or the client is done.
pub fn run_client(
    config: &Config,
    client: &mut dyn LoopClient,
    seconds: f64,
    camera: CameraChoice,
) -> anyhow::Result<LoopResult> {
    let shown = "scenario";
    match config.driver.kind {
        DriverChoice::Sim => {
            let (sim, parts) = upm_core::plate_driver::simulator(config, shown)?;
            run_on(config, sim, parts, client, seconds, camera)
        }
        DriverChoice::EthercatSim => {
            let (driver, parts) = upm_core::plate_driver::ethercat_sim(config, shown)?;
            run_on(config, driver, parts, client, seconds, camera)
        }
        DriverChoice::Ethercat => anyhow::bail!(
            "driver.kind = \"ethercat\" moves a real plate in real time; a lock-step run needs a simulated one \
             (\"sim\" or \"ethercat-sim\")"
        ),
    }
}

fn run_on<D: SimulatedPlant>(
    config: &Config,
    driver: D,
    parts: SimParts,
    client: &mut dyn LoopClient,
    seconds: f64,
    camera: CameraChoice,
) -> anyhow::Result<LoopResult> {
    let params = config.core_params("scenario")?;
    let mut core = Lockstep::new(&params, driver, 1_000_000_000).map_err(|e| anyhow::anyhow!("{e}"))?;
    let templates = upm_core::core_process::truth_templates(&parts);
    let tick_hz = params.motion.tick_hz;
    let frame_ticks = (tick_hz / config.vision.frame_hz).round().max(1.0) as u64;
    let total = (seconds * tick_hz) as u64;
    let mut sight = match camera {
        CameraChoice::Truth => Sight::Truth(Box::new(TruthSight::new(config)?)),
        CameraChoice::Rendered => Sight::Rendered(Box::new(RenderedSight::new(config)?)),
    };
    let mut seen = PartStates::new();
    let mut states = PartStates::new();
    let mut trails = Trails::default();
    let start_ns = core.now_ns();
    let tick_ns = 1e9 / tick_hz;
    let mut seq = 0;
    let mut t = 0;
    let mut next_frame = 0;
    let mut going = true;
    while t < total && going {
        let now = core.now_ns();
        if t == next_frame {
            next_frame += frame_ticks;
            core.motor().driver().with_simulator(&mut |sim| sim.write_ground_truth(&templates, &mut states));
            seq += 1;
            states.seq = seq;
            states.stamp_ns = now;
            let time = (now - start_ns) as f64 / 1e9;
            for p in states.parts() {
                trails.push(p.id, p.class, [time, p.x, p.y, p.theta]);
            }
            match &mut sight {
                Sight::Truth(s) => s.capture(&states),
                Sight::Rendered(s) => {
                    s.see(&states, frame_ticks as f64 / tick_hz, &mut seen);
                    going = going && deliver(&mut core, client, &seen, start_ns);
                }
            }
        }
        if let Sight::Truth(s) = &mut sight {
            while s.next(now, &mut seen) {
                going = going && deliver(&mut core, client, &seen, start_ns);
            }
        }
        // Step to the next frame, or to the next delivery if sooner.
        let mut until = next_frame.min(total);
        if let Sight::Truth(s) = &sight
            && let Some(ready) = s.next_ready_ns()
        {
            let ticks = ((ready.saturating_sub(now)) as f64 / tick_ns).ceil().max(1.0) as u64;
            until = until.min(t + ticks);
        }
        core.run_ticks(until - t, |_| {});
        t = until;
    }
    let mut feed = None;
    let ran = t as f64 / tick_hz;
    core.motor().driver().with_simulator(&mut |sim| feed = crate::feed_metrics::FeedOutcome::of(sim, ran));
    let sh = core.shared();
    Ok(LoopResult {
        feed,
        trails,
        hold_events: sh.hold_events.load(core::sync::atomic::Ordering::Relaxed),
        rejected_requests: sh.rejected_requests.load(core::sync::atomic::Ordering::Relaxed),
        saturated_schedules: core.published().iter().filter(|s| s.saturated != 0).count(),
        schedules: core.published().len(),
        k_max: core.stage().k_max(),
        first_rank_condition: core.published().first().map_or((0, 0.0), |s| (s.rank, s.condition)),
        mean_residual: core.published().iter().map(|s| s.residual).sum::<f64>()
            / core.published().len().max(1) as f64,
        sight: match sight {
            Sight::Truth(_) => None,
            Sight::Rendered(s) => Some((s.counts().detected, s.counts().merged, s.bad_frames)),
        },
    })
}

/// What the planner sees in lock-step.
enum Sight {
    Truth(Box<TruthSight>),
    Rendered(Box<RenderedSight>),
}

/// Hand a frame to the core and the client, as vision's publish does;
/// the client's answer follows at once. False when the client is done.
fn deliver<D: SimulatedPlant>(
    core: &mut Lockstep<D>,
    client: &mut dyn LoopClient,
    seen: &PartStates,
    start_ns: u64,
) -> bool {
    core.inbox().push_parts(seen);
    let now = core.now_ns();
    let time = seen.stamp_ns.saturating_sub(start_ns) as f64 / 1e9;
    client.answer(seen, time, now, core.inbox())
}
