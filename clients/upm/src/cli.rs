//! The `upm` command line (ARCHITECTURE.md §7). Parsing only; each subcommand's
//! work lives in its own module.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use ipc_types::CoreCommand;
pub use upm_commands::exit::Exit;

#[derive(Debug, Parser)]
#[command(
    name = "upm",
    version,
    about = "Universal planar manipulator: force synthesis, simulation and the closed loop"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Force synthesis: JSON in (a file or `-` for stdin), JSON out.
    Solve {
        /// Input JSON file, or `-` for stdin.
        file: PathBuf,
    },
    /// The camera client (same as `upm-vision`).
    #[command(hide = true)]
    Vision(upm_vision::args::VisionArgs),
    /// The rendered camera (same as `upm-camera`).
    #[command(hide = true)]
    Camera(upm_camera::args::CameraArgs),
    /// The planner client (same as `upm-planner`).
    #[command(hide = true)]
    Planner(upm_planner::args::PlannerArgs),
    /// The flight recorder (same as `upm-recorder`); `upm run` starts it so.
    #[command(hide = true)]
    Recorder(upm_recorder::args::RecorderArgs),
    /// Replay a recording (`run.mcap`): feed its part states and requests
    /// to a lock-step core and compare every schedule bit for bit. Exit 0
    /// identical, 1 divergent, 2 unreadable.
    Replay {
        file: PathBuf,
        /// Feed the recorded part states to this planner instead (open
        /// loop) and write what comes out to --out.
        #[arg(long)]
        planner: Option<String>,
        /// With --planner: the new recording.
        #[arg(long, default_value = "replay.mcap")]
        out: PathBuf,
        /// Print JSON instead of a line.
        #[arg(long)]
        json: bool,
    },
    /// Live view of a running rig: its channels (as recorded) over
    /// Foxglove's WebSocket protocol on localhost, until Ctrl-C.
    Monitor {
        /// The rig's service prefix (`upm status` lists running rigs).
        #[arg(long)]
        prefix: Option<String>,
        /// Rig config ([service], [plate]) for the scene; built-in defaults without.
        #[arg(long)]
        config: Option<PathBuf>,
        #[arg(long, default_value_t = 8765)]
        port: u16,
    },
    /// The closed loop: core, vision and planner as separate processes.
    Run {
        /// Scenario name (scenarios/NAME.toml) or path.
        scenario: String,
        /// Output directory (metrics.json, trails.svg, latency/*.hgrm).
        #[arg(long, default_value = "out/run")]
        out: PathBuf,
        /// Override the scenario's duration (s).
        #[arg(long)]
        duration: Option<f64>,
        /// Override the scenario's seed.
        #[arg(long)]
        seed: Option<u64>,
        /// The simulated plate's hidden truth, instead of the scenario's
        /// `[sim] truth`: `nominal`, `worn` or `random:SEED`.
        #[arg(long)]
        truth: Option<String>,
        /// A plate calibration (`upm calibrate plate`) for core and
        /// planner, instead of the scenario's `[calibration] file`.
        #[arg(long)]
        calibration: Option<PathBuf>,
        /// The planner learns each part's friction online
        /// (`[planner.drive] adapt_friction`).
        #[arg(long)]
        adapt: bool,
        /// Service prefix (default: one per run).
        #[arg(long)]
        prefix: Option<String>,
        /// A feed cell's recipe (recipes/NAME.toml or a path) instead of
        /// the scenario's.
        #[arg(long)]
        recipe: Option<PathBuf>,
        /// Load every CPU but the motor's during the run (stress-ng if
        /// installed, else a built-in burner); metrics.json names it.
        #[arg(long)]
        stress: bool,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Your own planner instead of upm-planner: a shell command line,
        /// run with UPM_PREFIX and UPM_CONFIG set, restarted if it dies.
        #[arg(long)]
        planner_cmd: Option<String>,
        /// Your own camera client instead of upm-vision (same rules).
        #[arg(long)]
        vision_cmd: Option<String>,
        /// Where vision's part poses come from: `truth` (the simulator's
        /// ground truth with noise, a fast test double) or `rendered` (a
        /// rendered camera process publishing frames, and vision's image
        /// pipeline).
        #[arg(long, value_enum, default_value_t = upm_commands::launcher::CameraChoice::Truth)]
        camera: upm_commands::launcher::CameraChoice,
        /// What moves the plate, instead of the scenario's `[driver]`:
        /// `sim` (the physics simulator), `ethercat-sim` (the EtherCAT
        /// driver over a simulated chain of CiA 402 drives whose servos
        /// move the simulator, in process) or `ethercat` (drives on
        /// `driver.interface`).
        #[arg(long, value_enum)]
        driver: Option<upm_commands::config::DriverChoice>,
        /// Do not record the run (by default upm-recorder writes every
        /// message to OUT/run.mcap).
        #[arg(long)]
        no_record: bool,
        /// Serve the live view (Foxglove WebSocket) on this localhost port.
        #[arg(long, num_args = 0..=1, default_missing_value = "8765")]
        monitor: Option<u16>,
        /// Serve OPC UA on this address (`upm line`), e.g. 127.0.0.1:4840.
        #[arg(long)]
        opcua: Option<String>,
        /// Serve Modbus TCP on this address (`upm line`), e.g. 127.0.0.1:5020.
        #[arg(long)]
        modbus: Option<String>,
        /// Serve the operator page (`upm hmi`) on this address, e.g.
        /// 127.0.0.1:8080.
        #[arg(long)]
        hmi: Option<String>,
        /// The users file of `upm line` and `upm hmi` (`upm users add`).
        #[arg(long)]
        users: Option<PathBuf>,
        /// Who takes the feed cell's parts: the simulator's own robot, or
        /// one outside that reports its picks (e.g. an OPC UA client
        /// calling `Rig.Picked` through `--opcua`).
        #[arg(long, value_enum)]
        robot: Option<RobotChoice>,
        /// Print metrics.json on stdout instead of a short summary.
        #[arg(long)]
        json: bool,
    },
    /// Benchmarks side by side with their references (BENCHMARKS.md).
    Bench {
        what: BenchTarget,
        /// Print JSON (ARCHITECTURE.md §7) instead of a table.
        #[arg(long)]
        json: bool,
        /// Shorter runs (smoke test).
        #[arg(long)]
        quick: bool,
        /// latency: seconds per run.
        #[arg(long, default_value_t = 5.0)]
        seconds: f64,
        /// latency, hmi: A/B rounds.
        #[arg(long, default_value_t = 2)]
        rounds: usize,
        /// latency: draw upm vs cyclictest distributions into this SVG.
        #[arg(long)]
        plot: Option<PathBuf>,
        /// latency: repeat the rounds under CPU load on the other CPUs
        /// (stress-ng if installed, else a built-in burner).
        #[arg(long)]
        stress: bool,
        /// solver: bench these problems instead (JSON Lines, one `upm
        /// solve` input per line); malformed lines are reported and make
        /// the exit status non-zero.
        #[arg(long)]
        problems: Option<PathBuf>,
        /// sort: how many seeds.
        #[arg(long, default_value_t = 32)]
        seeds: u64,
        /// sort: the first seed.
        #[arg(long, default_value_t = 1)]
        first_seed: u64,
        /// sort, feed: the scenario (default `sort`, `feed`; sort's
        /// planner must be sort or sort_paper, feed's present).
        #[arg(long)]
        scenario: Option<String>,
        /// sort: the reference scenario run on the same seeds ("none":
        /// none); feed: "none" skips the shake-and-pick baseline.
        #[arg(long, default_value = "sort_paper")]
        baseline: String,
        /// sort: what the planner sees (`rendered`: rendered frames through
        /// vision's pipeline, in the same process).
        #[arg(long, value_enum, default_value_t = upm_commands::launcher::CameraChoice::Truth)]
        camera: upm_commands::launcher::CameraChoice,
        /// sort: what moves the plate, instead of the scenario's `[driver]`
        /// (`ethercat-sim`: the EtherCAT driver over the simulated chain).
        #[arg(long, value_enum)]
        driver: Option<upm_commands::config::DriverChoice>,
        /// sort: the simulated plate's hidden truth (`nominal`, `worn`,
        /// `random:SEED`), instead of the scenarios' `[sim] truth`.
        #[arg(long)]
        truth: Option<String>,
        /// feed: the recipe instead of `scenarios/feed.toml`'s.
        #[arg(long)]
        recipe: Option<PathBuf>,
        /// feed: simulated minutes per seed.
        #[arg(long, default_value_t = 10.0)]
        minutes: f64,
        /// fidelity: how many random geometries.
        #[arg(long, default_value_t = 50)]
        cases: usize,
        /// fidelity: the seed of the geometries.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Calibrate the camera from its view of the calibration board
    /// (`[camera.board]`): rendered by the rig's `[camera]`, or PNG files.
    Calibrate {
        what: CalibrateTarget,
        /// Rig config ([camera], [plate]); the built-in defaults without it.
        /// plate: the running rig's file (with --prefix).
        #[arg(long)]
        config: Option<PathBuf>,
        /// camera: PNG images of the board from a real camera, instead of rendering.
        #[arg(long)]
        images: Option<PathBuf>,
        /// Where to write the calibration file (camera: calibration.toml,
        /// which vision loads; plate: plate-calibration.toml, which core and
        /// planner load through `[calibration] file`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// plate: calibrate the rig running at this prefix (with --config).
        #[arg(long)]
        prefix: Option<String>,
        /// plate: otherwise start this scenario's simulated rig for it
        /// (default `calibrate`).
        #[arg(long)]
        scenario: Option<String>,
        /// plate: the scenario's seed.
        #[arg(long)]
        seed: Option<u64>,
        /// plate: the simulated plate's hidden truth (`nominal`, `worn`, `random:SEED`).
        #[arg(long)]
        truth: Option<String>,
        /// plate: in lock-step, in this process (much faster than real time).
        #[arg(long)]
        lockstep: bool,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Snapshot of a running core's telemetry. Without --prefix or
    /// --config it finds the running rig by itself (several: lists them).
    Status {
        /// Print JSON (ARCHITECTURE.md §7) instead of text.
        #[arg(long)]
        json: bool,
        /// Service prefix of the rig (default: the running rig's).
        #[arg(long)]
        prefix: Option<String>,
        /// Rig config to take the prefix from.
        #[arg(long)]
        config: Option<PathBuf>,
        /// How long to wait for telemetry (s).
        #[arg(long, default_value_t = 2.0)]
        timeout: f64,
    },
    /// The sort scenario over and over while clients and the core are
    /// killed at random; reports holds, restarts, input ages, allocations,
    /// overruns and failures (a benchmark, see BENCHMARKS.md).
    Soak {
        /// How long (minutes).
        #[arg(long, default_value_t = 30.0)]
        minutes: f64,
        /// Seed of the kill schedule and of the runs.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output directory (one run-NNN/ per run, soak.json).
        #[arg(long, default_value = "out/soak")]
        out: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// End a driver-fault hold: the core plays again from its next cycle.
    Resume {
        /// Service prefix of the rig (default: the running rig's).
        #[arg(long)]
        prefix: Option<String>,
        /// Rig config to take the prefix from.
        #[arg(long)]
        config: Option<PathBuf>,
    },
    /// Stop the plate: at its next cycle boundary it is home and stays
    /// there (state idle) until `upm start`.
    Stop {
        /// Service prefix of the rig (default: the running rig's).
        #[arg(long)]
        prefix: Option<String>,
        /// Rig config to take the prefix from.
        #[arg(long)]
        config: Option<PathBuf>,
    },
    /// The line interface on a running rig: OPC UA and Modbus TCP for
    /// robots and PLCs (runs `upm-line`; `upm line --help` lists its flags).
    #[command(disable_help_flag = true)]
    Line {
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// The operator page on a running rig: the live plate, its counters
    /// and its controls in a browser (runs `upm-hmi`; `upm hmi --help`
    /// lists its flags: `--prefix P`, `--addr 127.0.0.1:8080`, `--users FILE`).
    #[command(disable_help_flag = true)]
    Hmi {
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// The users file of the line interface and the operator page.
    Users {
        #[command(subcommand)]
        action: UsersAction,
    },
    /// End an operator's stop: the plate plays schedules again.
    Start {
        /// Service prefix of the rig (default: the running rig's).
        #[arg(long)]
        prefix: Option<String>,
        /// Rig config to take the prefix from.
        #[arg(long)]
        config: Option<PathBuf>,
    },
    /// Solve, then play the schedule on the physics simulator and report the
    /// forces and curls the parts really feel.
    Validate {
        /// Input JSON file (same format as `solve`), or `-` for stdin.
        file: PathBuf,
        /// Cycles to simulate and average over.
        #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=10_000))]
        cycles: u64,
        /// Seed of the start-position jitter.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Write an SVG of the average force field (like the paper's Fig. 7).
        #[arg(long)]
        plot: Option<PathBuf>,
    },
}

/// What `upm calibrate` calibrates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CalibrateTarget {
    /// The camera: intrinsics, distortion and pose over the plate.
    Camera,
    /// The plate: how it really turns about each center, and its friction
    /// per part class and over the plate, from the parts on it.
    Plate,
}

/// Who takes a feed cell's parts in `upm run`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RobotChoice {
    /// The simulator's robot (the scenario's `[feed] robot`).
    Builtin,
    /// A robot outside, through `upm/pick` (`upm line`'s `Rig.Picked`).
    External,
}

/// What `upm users` does.
#[derive(Debug, Subcommand)]
pub enum UsersAction {
    /// Add a user (the file is created if missing; it holds argon2 hashes,
    /// never a password).
    Add {
        file: PathBuf,
        name: String,
        /// Read the password from the first line of stdin.
        #[arg(long)]
        password_stdin: bool,
    },
}

/// What `upm bench` measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchTarget {
    /// Solver vs nalgebra's pseudo-inverse.
    Solver,
    /// Motor-thread wake-up vs cyclictest.
    Latency,
    /// One-way PartStates latency vs raw iceoryx2 ping-pong.
    Ipc,
    /// Time to sort, lock-step, over many seeds.
    Sort,
    /// Forces and curls on extended parts: the per-shape model vs the
    /// paper's point model, played on the simulator.
    Fidelity,
    /// Plates that are not what the model says (random hidden truths):
    /// force error and track RMS, nominal model vs `calibrate plate`.
    Calibration,
    /// The camera path: accuracy against the rendered truth, time per
    /// frame beside OpenCV on the same frames.
    Vision,
    /// EtherCAT process-data round trip over veth at 1 and 4 kHz, the
    /// driver's motor-thread poll beside ethercrab's io_uring task, with
    /// the cycle thread's wake-up (needs root).
    Ethercat,
    /// The flight recorder and live view: the core's p99 without and with
    /// them, bytes per minute, replay speed.
    Record,
    /// A feed cell, lock-step: the `present` planner beside the feeders'
    /// shake-and-pick on the same seeds and recipe.
    Feed,
    /// The line interface: a robot on OPC UA beside the simulator's own
    /// robot (`upm run feed`, same seed), `Picked`'s round trip, a part
    /// turning ready → `Ready` at the robot, and the core's motor p99 while
    /// 200 clients connect and drop. Each run lasts 90 s (`--seconds`
    /// above 5 sets it; `--quick`: 55 s, and 20 clients in 20 s); `--seed`.
    Line,
    /// The operator page: the core's motor and solver p99 with 10 pages
    /// open against none, `upm run feed --hmi` in alternating pairs
    /// (`--rounds`, default 2; each run 60 s, `--seconds` above 5 sets it;
    /// `--quick`: one round of 20 s); `--seed`.
    Hmi,
}

/// The rig a command talks to: `--prefix`, else the config's, else the
/// one running rig.
fn rig_prefix(prefix: Option<String>, config: Option<PathBuf>) -> anyhow::Result<String> {
    match (prefix, config) {
        (Some(p), _) => Ok(p),
        (None, Some(c)) => Ok(upm_commands::config::Config::load(&c)?.service.prefix),
        (None, None) => upm_commands::status::discover_prefix(),
    }
}

pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Solve { file } => {
            let text = upm_commands::input::read_input(&file)?;
            let input = upm_paper::solve_json::parse(&text)?;
            let out = upm_paper::solve_json::solve(&input)?;
            println!("{}", serde_json::to_string_pretty(&out)?);
            Ok(())
        }
        Command::Vision(args) => {
            let frames = upm_vision::args::run_vision(args)?;
            eprintln!("upm-vision: stopped after {frames} frames");
            Ok(())
        }
        Command::Camera(args) => {
            let frames = upm_camera::args::run_camera(args)?;
            eprintln!("upm-camera: stopped after {frames} frames");
            Ok(())
        }
        Command::Planner(args) => {
            let n = upm_planner::args::run_planner_process(args)?;
            eprintln!("upm-planner: stopped after {n} requests");
            Ok(())
        }
        Command::Run {
            scenario,
            out,
            duration,
            seed,
            truth,
            calibration,
            adapt,
            prefix,
            recipe,
            quiet,
            stress,
            planner_cmd,
            vision_cmd,
            camera,
            driver,
            no_record,
            monitor,
            opcua,
            modbus,
            hmi,
            users,
            robot,
            json,
        } => {
            let path = upm_commands::scenario::resolve(&scenario);
            let mut sc = upm_commands::scenario::Scenario::load(&path)?;
            if let Some(r) = &recipe {
                sc.use_recipe(&upm_commands::scenario::resolve_recipe_file(r))?;
            }
            let seed = seed.unwrap_or(sc.seed);
            let duration_s = match duration {
                Some(d) if d.is_finite() && d > 0.0 => d,
                Some(d) => anyhow::bail!("--duration must be a positive number of seconds, got {d}"),
                None => sc.duration_s,
            };
            let prefix = prefix.unwrap_or_else(|| format!("upm_run_{}_", std::process::id()));
            let mut config = sc.config(seed, &prefix)?;
            if let Some(kind) = driver {
                config.driver.kind = kind;
            }
            if let Some(t) = truth {
                config.sim.truth = upm_commands::config::truth::TruthSection::Preset(t);
            }
            if adapt {
                config.planner.drive_mut().adapt_friction = true;
            }
            if robot == Some(RobotChoice::External) {
                config.feed.use_external_robot().map_err(anyhow::Error::msg)?;
            }
            if let Some(f) = calibration {
                // Absolute: the processes start in other directories.
                config.calibration.file = Some(std::path::absolute(&f)?);
            }
            // Every section, as each process will check its own: a bad one
            // stops the run here, not in a client restarted over and over.
            upm_commands::config::validate(&config, &path.display().to_string())?;
            let round =
                |p: &upm_commands::config::SimPartSection| matches!(p.shape.as_str(), "disc" | "point");
            if camera == upm_commands::launcher::CameraChoice::Rendered
                && config.planner.name() == "spin"
                && config.sim.parts.iter().any(round)
            {
                anyhow::bail!(
                    "--camera rendered: the spin planner needs its part's angle, and vision cannot see a disc's \
                     (give the part a square or triangle shape, as scenarios/spin_square.toml does)"
                );
            }
            eprintln!("upm run: service prefix {prefix}; watch it with `upm status --prefix {prefix}`");
            // `--users` serves the line, the page or both.
            let line_users = users.clone().filter(|_| hmi.is_none() || opcua.is_some() || modbus.is_some());
            let plan = upm_commands::launcher::RunPlan {
                scenario: sc.name.clone(),
                seed,
                duration_s,
                config: config.clone(),
                stress,
                planner_cmd,
                planner_ends_run: false,
                vision_cmd,
                camera,
                record: !no_record,
                monitor,
                line: line_args(
                    opcua,
                    modbus,
                    line_users,
                    &sc.rig.feed.recipe,
                    robot == Some(RobotChoice::External),
                )?,
                hmi: hmi_args(hmi, users, &sc.rig.feed.recipe)?,
            };
            if let Some(port) = monitor {
                eprintln!("upm run: live view on ws://127.0.0.1:{port} (Foxglove: open connection)");
            }
            if let Some(addr) = plan.hmi.as_ref().and_then(|a| a.get(1)) {
                eprintln!("upm run: operator page on http://{addr}/");
            }
            let outcome = upm_commands::launcher::run_plan(&plan, &out, !quiet, &|t| sc.evaluate(&config, t));
            ipc_types::rig_node::remove_prefix_segment(&prefix);
            let outcome = outcome?;
            if json {
                println!("{}", serde_json::to_string_pretty(&outcome.metrics)?);
            } else {
                println!("{}", upm_commands::launcher::summary::summary(&outcome.metrics, &out, !no_record));
            }
            Ok(())
        }
        Command::Recorder(args) => upm_recorder::args::run_recorder_process(args),
        Command::Replay { file, planner, out, json } => {
            upm_commands::replay::run_command(&file, planner.as_deref(), &out, json)
        }
        Command::Monitor { prefix, config, port } => {
            let prefix = Some(rig_prefix(prefix, config.clone())?);
            let args = upm_recorder::args::RecorderArgs {
                process: rig_config::ProcessArgs { config, prefix, duration: None },
                out: None,
                serve: Some(port),
                frame_pixels: false,
                truth_hz: 100.0,
                segment_minutes: 0.0,
                info: Vec::new(),
            };
            upm_recorder::args::run_recorder_process(args)
        }
        Command::Bench {
            what,
            json,
            quick,
            seconds,
            rounds,
            plot,
            stress,
            problems,
            seeds,
            first_seed,
            scenario,
            baseline,
            camera,
            driver,
            truth,
            recipe,
            minutes,
            cases,
            seed,
        } => {
            let mut bad = 0;
            let (v, text): (serde_json::Value, fn(&serde_json::Value) -> String) = match (what, problems) {
                (BenchTarget::Solver, Some(file)) => {
                    let (v, b) = upm_bench::bench_solver::run_problems(&file, quick)?;
                    bad = b;
                    (v, upm_bench::bench_solver::bounded_text)
                }
                (_, Some(_)) => anyhow::bail!("--problems applies to `upm bench solver` only"),
                (BenchTarget::Solver, None) => {
                    (upm_bench::bench_solver::run(quick)?, upm_bench::bench_solver::to_text)
                }
                (BenchTarget::Latency, None) => {
                    let s = if quick { seconds.min(1.0) } else { seconds };
                    (
                        upm_bench::bench_latency::run_with_plot(s, rounds, plot.as_deref(), stress)?,
                        upm_bench::bench_latency::to_text,
                    )
                }
                (BenchTarget::Ipc, None) => {
                    let s = if quick { seconds.min(1.0) } else { seconds };
                    (upm_bench::bench_ipc::run(s)?, upm_bench::bench_ipc::to_text)
                }
                (BenchTarget::Calibration, None) => {
                    let cases = if quick { cases.min(2) } else { cases };
                    (
                        upm_bench::bench_calibration::run(cases, seed, quick)?,
                        upm_bench::bench_calibration::to_text,
                    )
                }
                (BenchTarget::Fidelity, None) => {
                    let cases = if quick { cases.min(3) } else { cases };
                    let loop_seeds = if quick { 1 } else { 3 };
                    (
                        upm_bench::bench_fidelity::run(cases, seed, loop_seeds)?,
                        upm_bench::bench_fidelity::to_text,
                    )
                }
                (BenchTarget::Sort, None) => {
                    // --quick: 30 simulated seconds per seed.
                    let b = upm_bench::bench_sort::SortBench {
                        scenario: scenario.unwrap_or_else(|| "sort".into()),
                        baseline: (baseline != "none").then_some(baseline),
                        seeds,
                        first_seed,
                        seconds: quick.then_some(30.0),
                        camera,
                        driver,
                        truth,
                    };
                    (upm_bench::bench_sort::run(&b)?, upm_bench::bench_sort::to_text)
                }
                (BenchTarget::Feed, None) => {
                    // --quick: 2 simulated minutes per seed.
                    let b = upm_bench::bench_feed::FeedBench {
                        scenario: scenario.unwrap_or_else(|| "feed".into()),
                        baseline: baseline != "none",
                        recipe: recipe.as_deref().map(upm_commands::scenario::resolve_recipe_file),
                        seeds,
                        first_seed,
                        minutes: if quick { 2.0 } else { minutes },
                    };
                    (upm_bench::bench_feed::run(&b)?, upm_bench::bench_feed::to_text)
                }
                (BenchTarget::Vision, None) => {
                    (upm_bench::bench_vision::run(quick)?, upm_bench::bench_vision::to_text)
                }
                (BenchTarget::Record, None) => {
                    let (s, r) = if quick { (seconds.min(5.0), 1) } else { (seconds, rounds) };
                    (upm_bench::bench_record::run(s, r)?, upm_bench::bench_record::to_text)
                }
                (BenchTarget::Line, None) => {
                    // `--seconds` keeps its default of 5 for the latency benches.
                    let s = match (quick, seconds > 5.0) {
                        (true, _) => upm_bench_cell::bench_line::QUICK_SECONDS,
                        (false, true) => seconds,
                        (false, false) => upm_bench_cell::bench_line::DEFAULT_SECONDS,
                    };
                    let b = upm_bench_cell::bench_line::LineBench {
                        seconds: s,
                        seed,
                        churn: if quick { 20 } else { 200 },
                        churn_seconds: if quick { 20.0 } else { s },
                    };
                    (upm_bench_cell::bench_line::run(&b)?, upm_bench_cell::bench_line::to_text)
                }
                (BenchTarget::Hmi, None) => {
                    let b = upm_bench_cell::bench_hmi::HmiBench {
                        seconds: match (quick, seconds > 5.0) {
                            (true, _) => upm_bench_cell::bench_hmi::QUICK_SECONDS,
                            (false, true) => seconds,
                            (false, false) => upm_bench_cell::bench_hmi::DEFAULT_SECONDS,
                        },
                        rounds: if quick { 1 } else { rounds },
                        seed,
                    };
                    (upm_bench_cell::bench_hmi::run(&b)?, upm_bench_cell::bench_hmi::to_text)
                }
                (BenchTarget::Ethercat, None) => {
                    let s = if quick { seconds.min(1.0) } else { seconds };
                    (upm_bench::bench_ethercat::run(s)?, upm_bench::bench_ethercat::to_text)
                }
            };
            if json {
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                println!("{}", text(&v));
            }
            if bad > 0 {
                anyhow::bail!("{bad} problem line(s) malformed or unsolvable (named above)");
            }
            Ok(())
        }
        Command::Soak { minutes, seed, out, json } => {
            if !(minutes.is_finite() && minutes > 0.0) {
                anyhow::bail!("--minutes must be a positive number, got {minutes}");
            }
            let plan = upm_commands::soak::SoakPlan {
                minutes,
                seed,
                out,
                kill_every_s: (20.0, 60.0),
                core_kill_every_s: 600.0,
            };
            let v = upm_commands::soak::run(&plan)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                println!("{}", upm_commands::soak::to_text(&v));
            }
            Ok(())
        }
        Command::Line { args } => {
            let exe = upm_commands::launcher::programs::own_binary("upm-line")?;
            let status = std::process::Command::new(&exe).args(&args).status()?;
            std::process::exit(status.code().unwrap_or(1));
        }
        Command::Hmi { args } => {
            let exe = upm_commands::launcher::programs::own_binary("upm-hmi")?;
            let status = std::process::Command::new(&exe).args(&args).status()?;
            std::process::exit(status.code().unwrap_or(1));
        }
        Command::Users { action: UsersAction::Add { file, name, password_stdin } } => {
            if !password_stdin {
                anyhow::bail!("upm users add: give the password on stdin with --password-stdin");
            }
            let mut password = String::new();
            std::io::stdin().read_line(&mut password)?;
            let password = password.trim_end_matches(['\n', '\r']);
            upm_users::add_user(&file, &name, password)?;
            eprintln!("upm users: added {name:?} to {}", file.display());
            Ok(())
        }
        Command::Resume { prefix, config } => operator_command("resume", CoreCommand::RESUME, prefix, config),
        Command::Stop { prefix, config } => operator_command("stop", CoreCommand::STOP, prefix, config),
        Command::Start { prefix, config } => operator_command("start", CoreCommand::START, prefix, config),
        Command::Calibrate {
            what: CalibrateTarget::Plate,
            config,
            images,
            out,
            prefix,
            scenario,
            seed,
            truth,
            lockstep,
            json,
        } => {
            if images.is_some() {
                anyhow::bail!("--images applies to `upm calibrate camera` only");
            }
            if prefix.is_some() && (scenario.is_some() || seed.is_some() || truth.is_some() || lockstep) {
                anyhow::bail!(
                    "--prefix calibrates a running rig: --scenario, --seed, --truth and --lockstep do not apply"
                );
            }
            if prefix.is_none() && config.is_some() {
                anyhow::bail!("--config names a running rig's file: it goes with --prefix");
            }
            let scenario = scenario.unwrap_or_else(|| "calibrate".into());
            let out = out.unwrap_or_else(|| "plate-calibration.toml".into());
            upm_commands::calibrate_plate::command(&upm_commands::calibrate_plate::PlateArgs {
                config,
                prefix,
                scenario,
                seed,
                truth,
                lockstep,
                out,
                json,
            })
        }
        Command::Calibrate {
            what: CalibrateTarget::Camera,
            config,
            images,
            out,
            json,
            prefix,
            scenario,
            seed,
            truth,
            lockstep,
        } => {
            if prefix.is_some() || scenario.is_some() || seed.is_some() || truth.is_some() || lockstep {
                anyhow::bail!(
                    "--prefix, --scenario, --seed, --truth and --lockstep apply to `upm calibrate plate` only"
                );
            }
            let out = out.unwrap_or_else(|| "calibration.toml".into());
            let shown = config.as_ref().map_or("built-in defaults".into(), |p| p.display().to_string());
            let config = match &config {
                Some(p) => upm_commands::config::Config::load(p)?,
                None => upm_commands::config::Config::default(),
            };
            let half_extent = config.plate.half_extent;
            config.camera.model().map_err(|m| upm_commands::config::ConfigError::invalid(&shown, m))?;
            let (cal, report) = match &images {
                Some(dir) => {
                    upm_commands::calibrate_camera::from_images(dir, &config.camera.board, half_extent)?
                }
                None => upm_commands::calibrate_camera::from_rendered(&config.camera, half_extent)?,
            };
            cal.save(&out).map_err(anyhow::Error::msg)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                println!("{report}");
            }
            eprintln!("upm calibrate: wrote {}", out.display());
            Ok(())
        }
        Command::Status { json, prefix, config, timeout } => {
            let prefix = rig_prefix(prefix, config)?;
            println!("{}", upm_commands::status::report(&prefix, timeout, json)?);
            Ok(())
        }
        Command::Validate { file, cycles, seed, plot } => {
            let text = upm_commands::input::read_input(&file)?;
            let input = upm_paper::solve_json::parse(&text)?;
            let out = upm_paper::validate::run(&input, cycles as usize, seed, plot.as_deref())?;
            println!("{}", serde_json::to_string_pretty(&out)?);
            Ok(())
        }
    }
}

/// Send the operator's `command` to the core of the rig.
fn operator_command(
    name: &str,
    command: u32,
    prefix: Option<String>,
    config: Option<PathBuf>,
) -> anyhow::Result<()> {
    let prefix = rig_prefix(prefix, config)?;
    upm_commands::status::send_command(&prefix, command)?;
    eprintln!("upm {name}: sent to the core on prefix {prefix:?}; `upm status --prefix {prefix}` shows it");
    Ok(())
}

/// `upm-line`'s arguments for `upm run --opcua/--modbus/--users`; None
/// when neither server is asked for.
fn line_args(
    opcua: Option<String>,
    modbus: Option<String>,
    users: Option<PathBuf>,
    recipe: &str,
    external_robot: bool,
) -> anyhow::Result<Option<Vec<String>>> {
    if opcua.is_none() && modbus.is_none() {
        if users.is_some() {
            anyhow::bail!(
                "--users is the line interface's and the page's: give --opcua, --modbus or --hmi too"
            );
        }
        return Ok(None);
    }
    let mut args = Vec::new();
    for (flag, value) in [("--opcua", opcua), ("--modbus", modbus)] {
        if let Some(v) = value {
            args.extend([flag.to_owned(), v]);
        }
    }
    if let Some(u) = users {
        // Absolute: the line starts in another directory.
        args.extend(["--users".to_owned(), std::path::absolute(&u)?.display().to_string()]);
    }
    // `LoadRecipe(NAME)` looks beside the running recipe.
    if let Some(dir) = recipes_dir(recipe)? {
        args.extend(["--recipes".to_owned(), dir]);
    }
    let robot = if external_robot { "external" } else { "builtin" };
    args.extend(["--robot".to_owned(), robot.to_owned()]);
    Ok(Some(args))
}

/// The recipes beside the running one (absolute: a client starts in
/// another directory), for `--recipes`; None without a recipe.
fn recipes_dir(recipe: &str) -> anyhow::Result<Option<String>> {
    let Some(dir) = std::path::Path::new(recipe).parent().filter(|_| !recipe.is_empty()) else {
        return Ok(None);
    };
    let dir = if dir.as_os_str().is_empty() { std::path::Path::new(".") } else { dir };
    Ok(Some(std::path::absolute(dir)?.display().to_string()))
}

/// `upm-hmi`'s arguments for `upm run --hmi ADDR [--users FILE]`; None
/// without `--hmi`.
fn hmi_args(
    hmi: Option<String>,
    users: Option<PathBuf>,
    recipe: &str,
) -> anyhow::Result<Option<Vec<String>>> {
    let Some(addr) = hmi else { return Ok(None) };
    let mut args = vec!["--addr".to_owned(), addr];
    if let Some(u) = users {
        // Absolute: the page starts in another directory.
        args.extend(["--users".to_owned(), std::path::absolute(&u)?.display().to_string()]);
    }
    if let Some(dir) = recipes_dir(recipe)? {
        args.extend(["--recipes".to_owned(), dir]);
    }
    Ok(Some(args))
}
