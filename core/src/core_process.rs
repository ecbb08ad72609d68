//! `upm-core --config F`: load and validate the config, build the driver
//! `[driver]` names (the physics simulator by default), and run the RT core
//! until SIGINT/SIGTERM.

use std::path::PathBuf;

use anyhow::Context;
use clap::Parser;
use rt_core::{CoreParams, RunOptions, RunReport, SimulatorOutputs, run_core_with_truth};

use crate::config::{CoreConfig, DriverChoice};
use crate::plate_driver::SimulatedPlant;

#[derive(Debug, Parser)]
#[command(name = "upm-core", version, about = "UPM real-time core: motor loop, solver, iceoryx2 messages")]
pub struct CoreArgs {
    /// `--config`: the core's sections are validated; the clients' are
    /// theirs (`upm run` validates the whole file).
    #[command(flatten)]
    pub process: rig_config::ProcessArgs,
    /// Write latency histograms (*.hgrm) here at exit.
    #[arg(long)]
    pub histograms: Option<PathBuf>,
    /// Publish the simulator's ground truth (for the simulated camera) at
    /// this rate in Hz; 0 = off.
    #[arg(long, default_value_t = 0.0)]
    pub truth_hz: f64,
}

/// Each simulated part's id, class and outline as the wire carries them,
/// in part order: what the simulator fills its ground truth from.
pub fn truth_templates(parts: &crate::config::SimParts) -> Vec<ipc_types::PartState> {
    (0..parts.specs.len().max(parts.ids.len()))
        .map(|i| {
            let id = parts.ids.get(i).copied().unwrap_or(i as u32 + 1);
            let class = parts.classes.get(i).copied().unwrap_or(0);
            let point = ipc_types::PartState::new(id, class, 0, [0.0; 3], [0.0; 3]);
            parts.specs.get(i).map_or(point, |s| with_outline(point, &s.shape))
        })
        .collect()
}

// Every simulator polygon fits the wire.
const _: () = assert!(drivers::sim::MAX_POLYGON_VERTICES <= ipc_types::MAX_SHAPE_VERTICES);

/// A part's outline in its body frame, as the simulator keeps it.
fn with_outline(state: ipc_types::PartState, shape: &drivers::sim::BodyShape) -> ipc_types::PartState {
    use drivers::sim::BodyShape;
    match shape.body_frame() {
        BodyShape::Point { .. } => state,
        BodyShape::Disc { radius } => state.with_disc(radius),
        BodyShape::Polygon { vertices, count } => state.with_polygon(&vertices[..count]).unwrap_or(state),
    }
}

/// Run on a simulated plate that publishes its parts' ground truth
/// `truth_hz` times a second (0: not at all), and its feed cell's status
/// at the camera's rate (10 Hz if the core was not told it).
fn run_simulated<D: SimulatedPlant>(
    params: &CoreParams,
    config: &CoreConfig,
    shown: &str,
    mut driver: D,
    parts: crate::config::SimParts,
    truth_hz: f64,
    options: &RunOptions,
) -> anyhow::Result<RunReport> {
    let truth = if truth_hz > 0.0 {
        let every = ((params.motion.tick_hz / truth_hz).round() as u64).max(1);
        let port = driver.publish_ground_truth(every, truth_templates(&parts));
        Some(port.context("--truth-hz: the simulator could not be reached to publish its ground truth")?)
    } else {
        None
    };
    let status_hz = if options.vision_frame_hz > 0.0 { options.vision_frame_hz } else { 10.0 };
    let feed = driver.publish_feed_status((1000.0 / status_hz).round() as u64);
    let picks = driver.accept_picks().map(|mailbox| -> Box<dyn FnMut(&ipc_types::PickCommand) + Send> {
        Box::new(move |c| {
            mailbox.post(c.pose, c.part_id);
        })
    });
    let recipes = crate::recipe_changeover::changeovers(config, shown, &mut driver)?;
    run_core_with_truth(params, driver, SimulatorOutputs { truth, feed, picks, recipes }, options)
        .context("upm-core")
}

/// Print the one-line summary of a finished run; a run whose thread died
/// is an error naming the thread and what happened.
pub fn report(report: &RunReport) -> anyhow::Result<()> {
    let t = &report.telemetry;
    if let Some(f) = &report.fault {
        anyhow::bail!(
            "{} {}: {}; the plate was held, {} ticks, {} rt allocations",
            f.source,
            f.cause,
            f.detail_str(),
            t.counters.ticks,
            t.counters.rt_thread_allocations
        );
    }
    eprintln!(
        "upm-core: stopped cleanly, plate home; {} ticks, {} cycles, {} overruns, {} hold events, {} rt allocations",
        t.counters.ticks,
        t.cycle,
        t.counters.overruns,
        t.counters.hold_events,
        t.counters.rt_thread_allocations
    );
    let i = &report.inertia;
    eprintln!(
        "upm-core: feed-forward plate mass ×{:.4}, inertia ×{:.4} of the model's ({} cycles updated, {} skipped)",
        i.scale[0], i.scale[1], i.updates, i.skipped
    );
    Ok(())
}

/// Run the core; prints one loud warning when it is not real-time.
pub fn run(args: CoreArgs) -> anyhow::Result<RunReport> {
    let (mut config, shown): (CoreConfig, _) = match &args.process.config {
        Some(p) => (CoreConfig::load(p)?, p.display().to_string()),
        None => (CoreConfig::default(), "built-in defaults".to_string()),
    };
    if let Some(prefix) = &args.process.prefix {
        config.service.prefix.clone_from(prefix);
    }
    let params = config.core_params(&shown)?;
    if !(args.truth_hz.is_finite() && args.truth_hz >= 0.0 && args.truth_hz <= params.motion.tick_hz) {
        anyhow::bail!("--truth-hz must be in 0..={}, got {}", params.motion.tick_hz, args.truth_hz);
    }
    let duration = args.process.duration().map_err(anyhow::Error::msg)?;
    let options = RunOptions {
        prefix: config.service.prefix.clone(),
        histogram_dir: args.histograms.clone().or_else(|| config.histogram_dir().map(Into::into)),
        duration,
        vision_frame_hz: config.vision_frame_hz(),
    };
    eprintln!(
        "upm-core: prefix {:?}, {} centers, {} Hz motor loop, driver {:?}, pid {}",
        options.prefix,
        params.plate.centers.len(),
        params.motion.tick_hz,
        config.driver.kind,
        std::process::id()
    );
    if std::env::var_os("UPM_ABORT_ON_RT_ALLOCATION").is_some() {
        // Debugging aid: stop at the first RT-thread allocation (run under gdb).
        rt_core::alloc_count::abort_on_rt_allocation(true);
    }
    let report = match config.driver.kind {
        DriverChoice::Sim => {
            let (sim, parts) = crate::plate_driver::simulator(&config, &shown)?;
            run_simulated(&params, &config, &shown, sim, parts, args.truth_hz, &options)?
        }
        DriverChoice::EthercatSim => match crate::plate_driver::ethercat_over_veth(&config, &shown)? {
            Ok((driver, parts)) => {
                eprintln!(
                    "upm-core: ethercat-sim over veth {} (the chain answers from its own network namespace)",
                    driver.interface()
                );
                let chain = driver.chain();
                let report = run_simulated(&params, &config, &shown, driver, parts, args.truth_hz, &options)?;
                if let Ok(rig) = chain.lock() {
                    let (events, missed) = rig
                        .chain
                        .devices
                        .iter()
                        .fold((0, 0), |(e, m), d| (e + d.sync0_events, m + d.sync0_missed));
                    eprintln!(
                        "upm-core: the simulated drives saw {events} SYNC0 events, {missed} of them without fresh targets"
                    );
                }
                report
            }
            Err(why) => {
                eprintln!("upm-core: ethercat-sim in process ({why})");
                let (driver, parts) = crate::plate_driver::ethercat_sim_with(
                    &config,
                    &shown,
                    crate::plate_driver::keep_real_time,
                )?;
                run_simulated(&params, &config, &shown, driver, parts, args.truth_hz, &options)?
            }
        },
        DriverChoice::Ethercat => {
            let driver = crate::plate_driver::ethercat(&config, &shown)?;
            run_core_with_truth(&params, driver, SimulatorOutputs::default(), &options).context("upm-core")?
        }
    };
    let rt = report.realtime;
    if !rt.is_realtime() {
        eprintln!(
            "upm-core: WARNING: NOT REAL-TIME (memory locked: {}, motor SCHED_FIFO: {}, solver SCHED_FIFO: {}). \
             Run as root or grant CAP_SYS_NICE, LimitRTPRIO and LimitMEMLOCK; `upm status` shows this too.",
            rt.memory_locked, rt.motor.fifo, rt.solver.fifo
        );
    }
    Ok(report)
}
