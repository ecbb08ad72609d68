//! `upm run SCENARIO`: start upm-core, upm-vision and upm-planner as
//! separate processes (which binaries: [`programs`]) on the scenario's own
//! service prefix, show progress, restart a client that dies (with
//! backoff), stop everything cleanly at the end or on Ctrl-C, and write
//! `metrics.json`, `trails.svg` and `latency/*.hgrm` into the output
//! directory.

pub mod observer;
pub mod plot;
pub mod process_group;
pub mod programs;
pub mod summary;
pub mod supervisor;

use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::{Context, bail};
use iceoryx2::node::NodeWaitFailure;
use iceoryx2::prelude::*;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{Value, json};

use crate::config::Config;
pub use observer::{Observer, PartTrail, Trails};
pub(crate) use programs::upm_exe;
use supervisor::Supervised;

/// Everything the launcher needs to run one scenario.
#[derive(Debug, Clone)]
pub struct RunPlan {
    pub scenario: String,
    pub seed: u64,
    pub duration_s: f64,
    /// The rig config all three processes get (with the scenario's parts
    /// and planner).
    pub config: Config,
    /// Your own planner or camera client instead of upm's: a shell command
    /// line, started with `UPM_PREFIX` and `UPM_CONFIG` (the rig file) in
    /// its environment and supervised like upm's own.
    pub planner_cmd: Option<String>,
    /// The planner's exit ends the run instead of a restart: a client with
    /// a job to finish (`upm calibrate plate`).
    pub planner_ends_run: bool,
    pub vision_cmd: Option<String>,
    /// Load every CPU but the motor's while the loop runs (see `cpu_load`).
    pub stress: bool,
    pub camera: CameraChoice,
    /// Record every message into `run.mcap` (upm-recorder).
    pub record: bool,
    /// Serve the live view on this localhost port (upm-recorder).
    pub monitor: Option<u16>,
    /// Start the line interface (upm-line) with these arguments (its
    /// `--opcua`, `--modbus`, `--users`, …); None: no line.
    pub line: Option<Vec<String>>,
    /// Start the operator page (upm-hmi) with these arguments (its
    /// `--addr`, `--users`, …); None: no page.
    pub hmi: Option<Vec<String>>,
}

/// The recording of a run, in the output directory.
pub const RECORDING: &str = "run.mcap";
/// A run's recording goes on in `run.001.mcap`, … after this long: a
/// file's chunk index stays in the recorder's memory until the file ends.
pub const SEGMENT_MINUTES: u32 = 10;

/// Where vision's part poses come from in a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CameraChoice {
    /// The simulator's ground truth with noise (vision's test double).
    Truth,
    /// A rendered camera process (`[camera]`) publishing frames, and
    /// vision's image pipeline with the rendered camera's calibration.
    Rendered,
}

/// What the run produced.
#[derive(Debug)]
pub struct RunOutcome {
    pub metrics: Value,
    pub trails: Trails,
    pub interrupted: bool,
}

fn latency_json(p: &ipc_types::LatencyPercentiles) -> Value {
    let us = |ns: u64| ns as f64 / 1e3;
    json!({ "p50": us(p.p50_ns), "p99": us(p.p99_ns), "p999": us(p.p999_ns), "max": us(p.max_ns), "samples": p.samples })
}

/// Run `plan`, writing into `out`. `evaluate` turns the trails into the
/// scenario's goal metrics (merged into metrics.json).
pub fn run_plan(
    plan: &RunPlan,
    out: &Path,
    show_progress: bool,
    evaluate: &dyn Fn(&Trails) -> Value,
) -> anyhow::Result<RunOutcome> {
    let prefix = plan.config.service.prefix.clone();
    if ipc_types::discovery::core_running(&prefix).map_err(|e| anyhow::anyhow!("{e}"))? {
        bail!(
            "a upm-core is already running on service prefix {prefix:?}; stop it first or use another prefix"
        );
    }
    let core_exe = programs::core_exe()?;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let mut config = plan.config.clone();
    let rendered = plan.camera == CameraChoice::Rendered;
    if rendered {
        // Vision gets what `upm calibrate camera` finds from the rendered
        // camera's view of the board, never the camera's true model.
        let (cal, report) = crate::calibrate_camera::from_rendered(&config.camera, config.plate.half_extent)?;
        let path = out.join("calibration.toml");
        cal.save(&path).map_err(anyhow::Error::msg)?;
        std::fs::write(out.join("calibration.json"), serde_json::to_string_pretty(&report)?)?;
        config.vision.source = rig_config::frame_rate::FRAMES_SOURCE.into();
        config.vision.calibration = path.display().to_string();
    }
    let cfg_path = out.join("config.toml");
    std::fs::write(&cfg_path, toml::to_string(&config).context("serialising the config")?)
        .with_context(|| format!("writing {}", cfg_path.display()))?;
    let logs = out.join("logs");
    std::fs::create_dir_all(&logs)?;
    let cfg = cfg_path.display().to_string();

    let mut core = Supervised::new(
        "upm-core",
        core_exe,
        vec![
            "--config".into(),
            cfg.clone(),
            "--truth-hz".into(),
            "1000".into(),
            "--histograms".into(),
            out.join("latency").display().to_string(),
        ],
        Some(logs.join("core.log")),
    );
    let client = |name: &'static str, own: &Option<String>, log: &str| -> anyhow::Result<Supervised> {
        let supervised = match own {
            Some(command) => Supervised::shell(name, command, Some(logs.join(log))),
            None => {
                let (program, mut args) = programs::client(name)?;
                args.extend(["--config".into(), cfg.clone()]);
                Supervised::new(name, program, args, Some(logs.join(log)))
            }
        };
        Ok(supervised
            .env("UPM_PREFIX", &prefix)
            .env("UPM_CONFIG", &cfg)
            .avoiding_cpu(plan.config.cpu_to_avoid()))
    };
    let vision_stats = out.join("vision_stats.json");
    let _ = std::fs::remove_file(&vision_stats);
    let mut vision = client("upm-vision", &plan.vision_cmd, "vision.log")?;
    if rendered && plan.vision_cmd.is_none() {
        vision = vision.arg("--stats").arg(&vision_stats.display().to_string());
    }
    let mut camera = rendered.then(|| client("upm-camera", &None, "camera.log")).transpose()?;
    let planner_stats = out.join("planner_stats.json");
    let _ = std::fs::remove_file(&planner_stats);
    let mut planner = client("upm-planner", &plan.planner_cmd, "planner.log")?;
    if plan.planner_cmd.is_none() {
        planner = planner.arg("--stats").arg(&planner_stats.display().to_string());
    }
    let recording = out.join(RECORDING);
    let recorder = (plan.record || plan.monitor.is_some()).then(|| -> anyhow::Result<Supervised> {
        let mut r = client("upm-recorder", &None, "recorder.log")?
            .arg("--info")
            .arg(&format!("scenario={}", plan.scenario))
            .arg("--info")
            .arg(&format!("seed={}", plan.seed));
        if plan.record {
            r = r.arg("--out").arg(&recording.display().to_string());
            r = r.arg("--segment-minutes").arg(&SEGMENT_MINUTES.to_string());
        }
        if let Some(port) = plan.monitor {
            r = r.arg("--serve").arg(&port.to_string());
        }
        Ok(r)
    });
    let mut recorder = recorder.transpose()?;
    // The line and the page are not linked into upm: each is refused
    // before the core starts if its binary is missing.
    let server =
        |name: &'static str, args: &Option<Vec<String>>, log: &str| -> anyhow::Result<Option<Supervised>> {
            let Some(args) = args else { return Ok(None) };
            programs::own_binary(name)?;
            let mut s = client(name, &None, log)?;
            for a in args {
                s = s.arg(a);
            }
            Ok(Some(s))
        };
    let mut line = server("upm-line", &plan.line, "line.log")?
        .map(|l| l.arg("--pki").arg(&out.join("pki").display().to_string()));
    let mut hmi = server("upm-hmi", &plan.hmi, "hmi.log")?;
    if plan.record {
        // The recorder never overwrites a file; this run's output is ours.
        let _ = std::fs::remove_file(&recording);
        for n in 1.. {
            if std::fs::remove_file(upm_recorder::segment_path(&recording, n)).is_err() {
                break;
            }
        }
    }

    let mut observer = Observer::new(&prefix, 20.0, crate::config::vision_publish_hz(&config))?;
    core.start()?;
    if let Some(cpu) = plan.config.cpu_to_avoid() {
        // The observer and progress bar need no RT CPU (the core, started
        // above, has taken the full set with it).
        let _ = rt_core::rt_setup::keep_current_thread_off(cpu);
    }
    // Wait until the core is up before starting its clients.
    let up = Instant::now();
    while !ipc_types::discovery::core_running(&prefix).unwrap_or(false) {
        if let Some(s) = core.exited() {
            bail!("{} at start-up", core.describe_end(s));
        }
        if up.elapsed() > Duration::from_secs(20) {
            bail!("upm-core did not come up within 20 s; see {}", logs.join("core.log").display());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    if let Some(r) = &mut recorder {
        r.start()?;
        wait_for_recorder(r, plan.record.then_some(recording.as_path()), &logs)?;
    }
    if let Some(c) = &mut camera {
        c.start()?;
    }
    if let Some(l) = &mut line {
        l.start()?;
    }
    if let Some(h) = &mut hmi {
        h.start()?;
    }
    vision.start()?;
    planner.start()?;
    let load = if plan.stress {
        Some(crate::cpu_load::CpuLoad::start(&crate::cpu_load::other_cpus(plan.config.rt_motor_cpu()))?)
    } else {
        None
    };

    // The launcher's own node handles Ctrl-C (SIGINT) and SIGTERM.
    let node = ipc_types::rig_node::rig_node(&prefix, None, SignalHandlingMode::HandleTerminationRequests)?;
    let bar =
        if show_progress { ProgressBar::new((plan.duration_s * 10.0) as u64) } else { ProgressBar::hidden() };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:40}] {pos}/{len} ds  (elapsed {elapsed})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(format!("{} seed {}", plan.scenario, plan.seed));
    let mut interrupted = false;
    let mut sim_s = 0.0;
    let mut core_failed = None;
    let mut planner_exit = None;
    // The line that ends the run: a client that cannot start.
    let mut fatal: Option<String> = None;
    let mut hung = HungWatch::new(&plan.config, !plan.planner_ends_run);
    let say = |msg: &str| if bar.is_hidden() { eprintln!("{msg}") } else { bar.println(msg) };
    while sim_s < plan.duration_s {
        sim_s = observer.poll()?;
        bar.set_position((sim_s * 10.0) as u64);
        if plan.planner_ends_run
            && let Some(s) = planner.exited()
        {
            planner_exit = Some(s);
            break;
        }
        hung.check(observer.last_telemetry.as_ref(), observer.parts_seen, &mut vision, &mut planner, &say);
        for c in [Some(&mut vision), Some(&mut planner), camera.as_mut(), line.as_mut(), hmi.as_mut()]
            .into_iter()
            .flatten()
        {
            if let Some(event) = c.restart_if_dead()? {
                if c.crash_looping() {
                    fatal = Some(event);
                } else {
                    say(&format!("upm run: {event}"));
                }
            }
        }
        if fatal.is_some() {
            break;
        }
        if let Some(s) = core.exited() {
            core_failed = Some(core.describe_end(s));
            break;
        }
        match node.wait(Duration::from_millis(20)) {
            Ok(()) => {}
            Err(NodeWaitFailure::Interrupt | NodeWaitFailure::TerminationRequest) => {
                interrupted = true;
                break;
            }
        }
    }
    bar.finish_and_clear();
    let stress = load.as_ref().map(|l| l.description().to_owned());
    drop(load);
    let _ = observer.poll();
    // Every process this run started, by its last pid (a restart changes it).
    let pids = json!({
        "launcher": std::process::id(),
        "core": core.pid(),
        "vision": vision.pid(),
        "planner": planner.pid(),
        "camera": camera.as_ref().and_then(Supervised::pid),
        "recorder": recorder.as_ref().and_then(Supervised::pid),
        "line": line.as_ref().and_then(Supervised::pid),
        "hmi": hmi.as_ref().and_then(Supervised::pid),
        "vision_cmd": plan.vision_cmd,
        "planner_cmd": plan.planner_cmd,
        "planner_exit": planner_exit.map(|s| s.to_string()),
    });
    let restarts = json!({
        "vision": vision.restarts,
        "planner": planner.restarts,
        "camera": camera.as_ref().map(|c| c.restarts),
    });
    planner.stop(Duration::from_secs(3));
    vision.stop(Duration::from_secs(3));
    if let Some(c) = &mut camera {
        c.stop(Duration::from_secs(3));
    }
    if let Some(l) = &mut line {
        l.stop(Duration::from_secs(3));
    }
    if let Some(h) = &mut hmi {
        h.stop(Duration::from_secs(3));
    }
    let core_exit = core.stop(Duration::from_secs(5));
    // Last, so it has the core's final telemetry.
    let recorder_exit = recorder.as_mut().and_then(|r| r.stop(Duration::from_secs(10)));
    let clients = json!({
        "vision": client_json(&vision),
        "planner": client_json(&planner),
        "camera": camera.as_ref().map(client_json),
        "recorder": recorder.as_ref().map(client_json),
        "line": line.as_ref().map(client_json),
        "hmi": hmi.as_ref().map(client_json),
    });
    let recording_json = if plan.record {
        crate::recording::summary_json(&recording, recorder_exit.is_some_and(|s| s.success()))
    } else {
        Value::Null
    };
    let t = observer.last_telemetry.unwrap_or_else(ipc_types::Telemetry::new);
    let mut metrics = json!({
        "scenario": plan.scenario,
        "seed": plan.seed,
        // For evaluation only: no process of the rig reads it.
        "truth": serde_json::to_value(&plan.config.sim.truth).unwrap_or(Value::Null),
        "sim_seconds": observer.trails.duration(),
        "interrupted": interrupted,
        "stress": stress,
        "core": {
            "cycles": t.cycle,
            "ticks": t.counters.ticks,
            "overruns": t.counters.overruns,
            "hold_events": t.counters.hold_events,
            "schedule_swaps": t.counters.schedule_swaps,
            "rt_thread_allocations": t.counters.rt_thread_allocations,
            "rejected_parts": t.counters.rejected_parts,
            "rejected_requests": t.counters.rejected_requests,
            "rejected_by_reason": crate::status::rejected_by_reason(&t),
            "realtime_flags": t.realtime_flags,
            "pm_qos_held": t.realtime_flags & ipc_types::Telemetry::RT_PM_QOS_HELD != 0,
            "driver": crate::status::driver_json(&t),
            "exit_ok": core_exit.is_some_and(|s| s.success()),
            "died": &core_failed,
        },
        "latency_us": {
            "motor_wakeup": latency_json(&t.latency.motor_wakeup),
            "solver": latency_json(&t.latency.solver),
            "ipc_vision_to_core": latency_json(&t.latency.ipc_vision_to_core),
            "frame_to_schedule": latency_json(&t.latency.frame_to_schedule),
        },
        // Of the schedules the launcher saw (it may miss some when it falls
        // behind; the core's solver histogram above has them all).
        "frames_late": observer.frames_late,
        "schedules_seen": observer.schedules_seen,
        "processes": pids,
        "restarts": restarts,
        // Each client's command, restarts, hung kills and how it last ended.
        "clients": clients,
        "camera": if rendered { "rendered" } else { "truth" },
        "recording": recording_json,
        // What vision did with the frames (rendered camera only).
        "vision": std::fs::read_to_string(&vision_stats).ok().and_then(|t| serde_json::from_str::<Value>(&t).ok()),
        "planner": planner_json(&plan.config, &planner_stats, &observer.trails),
    });
    if let (Value::Object(m), Value::Object(goals)) = (&mut metrics, evaluate(&observer.trails)) {
        m.extend(goals);
    }
    if let Some(feed) = observer.feed.outcome() {
        let mut v = feed.to_json();
        v["invalid_messages"] = json!(observer.feed.invalid);
        metrics["feed"] = v;
    }
    std::fs::write(out.join("metrics.json"), serde_json::to_string_pretty(&metrics)?)?;
    plot::draw_trails(
        &out.join("trails.svg"),
        &format!("{} (seed {})", plan.scenario, plan.seed),
        plan.config.plate.half_extent,
        &plan.config.plate.centers,
        &pick_marks(observer.feed.last.as_ref()),
        &observer.trails,
    )?;
    // What was recorded is written first: a dead core loses nothing.
    if let Some(line) = &core_failed {
        bail!("{line}; the run stopped; what was recorded is in {}", out.display());
    }
    if let Some(line) = fatal {
        bail!("{line}, so the run stops; what was recorded is in {}", out.display());
    }
    if observer.schedules_seen == 0 && !interrupted {
        bail!(
            "the {} never had a request accepted in {:.1} s ({} requests rejected{}; see {})",
            planner.label(),
            observer.trails.duration(),
            t.counters.rejected_requests,
            rejected_reasons(&t),
            logs.join("planner.log").display()
        );
    }
    Ok(RunOutcome { metrics, trails: observer.trails, interrupted })
}

/// `: stale 3, unknown_part 1` for the reasons with rejections, else "".
fn rejected_reasons(t: &ipc_types::Telemetry) -> String {
    let reasons = crate::status::rejected_by_reason(t);
    let each: Vec<String> = reasons.iter().map(|(r, n)| format!("{r} {n}")).collect();
    if each.is_empty() { String::new() } else { format!(": {}", each.join(", ")) }
}

/// A feed cell's pick poses as its last status gave them.
fn pick_marks(feed: Option<&ipc_types::FeedStatus>) -> Vec<plot::PickMark> {
    feed.map_or_else(Vec::new, |f| f.poses().iter().map(|p| (p.class, [p.x, p.y, p.theta])).collect())
}

/// What metrics.json keeps of a client.
fn client_json(c: &Supervised) -> Value {
    json!({
        "command": c.label(),
        "restarts": c.restarts,
        "hung_kills": c.hung_kills,
        "last_exit": c.last_exit,
    })
}

/// Clients that are alive but whose output the core has not accepted for
/// longer than its staleness limit, for `HUNG_GRACE`: killed and restarted.
#[derive(Debug)]
struct HungWatch {
    /// False for a planner with a job to finish (its exit ends the run):
    /// it may go quiet to compute once it has played what it needed.
    judge_planner: bool,
    parts_limit_ms: f64,
    request_limit_ms: f64,
    vision_since: Option<Instant>,
    planner_since: Option<Instant>,
}

/// How long a client's output may stay stale before it counts as hung
/// (counted from its start at the earliest, so a slow start is not hung).
const HUNG_GRACE: Duration = Duration::from_secs(5);

impl HungWatch {
    fn new(config: &Config, judge_planner: bool) -> Self {
        Self {
            judge_planner,
            parts_limit_ms: config.safety.parts_max_age_ns as f64 / 1e6,
            request_limit_ms: config.safety.request_max_age_ns as f64 / 1e6,
            vision_since: None,
            planner_since: None,
        }
    }

    /// Judge vision by the part states' age and the planner by the
    /// request's while the part states are fresh and name a part (a
    /// planner without parts has nothing to answer).
    fn check(
        &mut self,
        t: Option<&ipc_types::Telemetry>,
        parts_seen: Option<usize>,
        vision: &mut Supervised,
        planner: &mut Supervised,
        say: &dyn Fn(&str),
    ) {
        // Only on a current snapshot: a frozen core is not its clients' fault.
        let Some(t) = t.filter(|t| ipc_types::monotonic_now_ns().saturating_sub(t.stamp_ns) < 1_000_000_000)
        else {
            return;
        };
        let parts_stale = t.parts_age_ms > self.parts_limit_ms;
        let request_stale = self.judge_planner
            && t.request_age_ms > self.request_limit_ms
            && !parts_stale
            && parts_seen.is_some_and(|n| n > 0);
        let judged = [
            (vision, &mut self.vision_since, parts_stale, "part states", t.parts_age_ms, self.parts_limit_ms),
            (
                planner,
                &mut self.planner_since,
                request_stale,
                "request",
                t.request_age_ms,
                self.request_limit_ms,
            ),
        ];
        for (client, since, stale, what, age_ms, limit_ms) in judged {
            let Some(up) = client.uptime() else {
                *since = None;
                continue;
            };
            if !stale {
                *since = None;
                continue;
            }
            // Stale since this start at the earliest.
            let from =
                *since.get_or_insert_with(|| Instant::now() - up.min(Duration::from_millis(age_ms as u64)));
            if from.elapsed() >= HUNG_GRACE {
                let why = format!(
                    "alive, but no {what} accepted for {:.1} s, limit {:.0} ms",
                    age_ms / 1e3,
                    limit_ms
                );
                say(&format!("upm run: {}", client.kill_hung(&why)));
                *since = None;
            }
        }
    }
}

/// Wait until upm-recorder listens: its file exists (it subscribes first)
/// or, serving only, its log names the port.
fn wait_for_recorder(r: &mut Supervised, file: Option<&Path>, logs: &Path) -> anyhow::Result<()> {
    let log = logs.join("recorder.log");
    let up = Instant::now();
    loop {
        let ready = match file {
            Some(f) => f.exists(),
            None => std::fs::read_to_string(&log).is_ok_and(|t| t.contains("ws://")),
        };
        if ready {
            return Ok(());
        }
        if let Some(s) = r.exited() {
            bail!("upm-recorder exited at start-up ({s}); see {}", log.display());
        }
        if up.elapsed() > Duration::from_secs(20) {
            bail!("upm-recorder did not start within 20 s; see {}", log.display());
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// What the planner learnt (its `--stats` file), each friction estimate
/// beside the simulated plate's truth where the part was last seen: the
/// launcher may read the truth for evaluation, the planner never does.
fn planner_json(config: &Config, stats: &Path, trails: &Trails) -> Value {
    let Some(mut v) =
        std::fs::read_to_string(stats).ok().and_then(|t| serde_json::from_str::<Value>(&t).ok())
    else {
        return Value::Null;
    };
    let count = upm_motion::RigParams::default().count;
    let truth = config.sim.truth.resolve(count, config.plate.half_extent).ok();
    if let (Some(truth), Some(list)) = (truth, v["friction_estimates"].as_array_mut()) {
        for e in list {
            let id = e["id"].as_u64().unwrap_or(u64::MAX) as u32;
            let Some(t) = trails.parts.get(&id) else { continue };
            let Some(last) = t.points.last() else { continue };
            e["truth"] = json!(truth.friction_at(t.class, last[1], last[2]));
        }
    }
    v
}
