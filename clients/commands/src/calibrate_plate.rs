//! `upm calibrate plate`: the plate calibration (`upm_calibrate`) against
//! a running rig, or in lock-step for the bench. Only what the controller
//! knows goes in (`[plate]`, `[motion]`, the core's k bounds and the
//! planner's μ·g); the simulator's `[sim]` never does.

use rig_config::PlateCalibration;
use rt_core::QueueInbox;
use upm_calibrate::{CalibrateSetup, ExciteParams, Exciter, Step};

use crate::closed_loop::LoopClient;
use crate::config::Config;

/// The calibration's view of the rig `config` describes.
pub fn setup(config: &Config, params: ExciteParams) -> anyhow::Result<CalibrateSetup> {
    // The core's threads and CPUs are none of this process's business (it
    // may run off the motor's CPU, where `rt.motor_cpu` would not check).
    let mut plate_only = config.clone();
    plate_only.rt.motor_cpu = None;
    let core = plate_only.core_params("config")?;
    let k_bounds = core.playable_k_bounds().map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut planner = config.planner.clone();
    let drive = planner.drive_mut();
    Ok(CalibrateSetup {
        centers: core.plate.centers.clone(),
        k_bounds,
        motion: core.motion,
        mu_m_g: core.plate.mu_m_g,
        mu_g: drive.mu_m_g / drive.part_mass,
        plate_half_extent: config.plate.half_extent,
        actuators: core.rig.count as u32,
        tracker_alpha: Some(config.vision.alpha),
        frame_period_s: 1.0 / config.vision.frame_hz,
        prior_correction: core.twist_correction,
        // The drives as the rig specifies them (not as a hidden truth has them).
        follow: config.sim_config("config")?.drive_servo().servo,
        params,
    })
}

/// The exciter as a lock-step client; keeps the first refusal.
struct Lockstepped {
    exciter: Exciter,
    seq: u64,
    failed: Option<upm_calibrate::CalibrateError>,
}

impl LoopClient for Lockstepped {
    fn answer(
        &mut self,
        seen: &ipc_types::PartStates,
        time: f64,
        now_ns: u64,
        inbox: &mut QueueInbox,
    ) -> bool {
        let mut msg = ipc_types::ExplicitSchedule::new();
        match self.exciter.on_frame(seen, time, &mut msg) {
            Ok(Step::Play) => {
                self.seq += 1;
                msg.seq = self.seq;
                msg.stamp_ns = now_ns;
                inbox.push_explicit(&msg);
                true
            }
            Ok(Step::Done) => false,
            Err(e) => {
                self.failed.get_or_insert(e);
                false
            }
        }
    }
}

/// Calibrate the plate of `config` in lock-step (the core, the simulator
/// and vision's camera model on one clock).
pub fn lockstep(config: &Config, params: ExciteParams) -> anyhow::Result<PlateCalibration> {
    let mut client = Lockstepped { exciter: Exciter::new(setup(config, params)?)?, seq: 0, failed: None };
    let limit = client.exciter.rig_seconds() + 2.0;
    crate::closed_loop::run_client(config, &mut client, limit, crate::launcher::CameraChoice::Truth)?;
    if let Some(e) = client.failed {
        return Err(e.into());
    }
    Ok(client.exciter.fit()?)
}

/// What `upm calibrate plate` was asked.
#[derive(Debug, Clone)]
pub struct PlateArgs {
    /// The rig's file, for a rig already running at `prefix`.
    pub config: Option<std::path::PathBuf>,
    pub prefix: Option<String>,
    /// Otherwise: this scenario's simulated rig, started for the purpose.
    pub scenario: String,
    pub seed: Option<u64>,
    pub truth: Option<String>,
    /// In lock-step (no processes, much faster than real time).
    pub lockstep: bool,
    pub out: std::path::PathBuf,
    pub json: bool,
}

/// `upm calibrate plate`: calibrate and write the file atomically.
pub fn command(a: &PlateArgs) -> anyhow::Result<()> {
    let cal = match &a.prefix {
        Some(prefix) => {
            let path = a
                .config
                .as_ref()
                .ok_or_else(|| anyhow::anyhow!("--prefix needs --config (the rig's file)"))?;
            let mut config = Config::load(path)?;
            // A simulated plate's truth is the simulator's alone.
            config.sim = crate::config::SimSection::default();
            let setup = setup(&config, ExciteParams::default())?;
            eprintln!(
                "upm calibrate plate: playing {:.0} s of excitation on rig {prefix}",
                setup.params.rig_seconds()
            );
            upm_calibrate::process::run_calibration(setup, prefix, std::time::Duration::from_secs(5))?
        }
        None => {
            let path = crate::scenario::resolve(&a.scenario);
            let sc = crate::scenario::Scenario::load(&path)?;
            let seed = a.seed.unwrap_or(sc.seed);
            let prefix = format!("upm_calibrate_{}_", std::process::id());
            let mut config = sc.config(seed, &prefix)?;
            if let Some(t) = &a.truth {
                config.sim.truth = crate::config::truth::TruthSection::Preset(t.clone());
            }
            crate::config::validate(&config, &path.display().to_string())?;
            if a.lockstep {
                lockstep(&config, ExciteParams::default())?
            } else {
                launched(&sc, seed, config, &a.out)?
            }
        }
    };
    let kept = cal.write_atomically(&a.out).map_err(anyhow::Error::msg)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&cal)?);
    } else {
        println!("{}", summary(&cal));
    }
    match kept {
        Some(old) => eprintln!(
            "upm calibrate plate: wrote {} (the previous one is {})",
            a.out.display(),
            old.display()
        ),
        None => eprintln!("upm calibrate plate: wrote {}", a.out.display()),
    }
    Ok(())
}

/// Start the scenario's rig without its planner and run this command
/// against it as the client; returns what the client wrote.
fn launched(
    sc: &crate::scenario::Scenario,
    seed: u64,
    config: Config,
    out: &std::path::Path,
) -> anyhow::Result<PlateCalibration> {
    let exe = crate::launcher::upm_exe()?;
    let staged = out.with_extension("staged.toml");
    let _ = std::fs::remove_file(&staged);
    let client = format!(
        "'{}' calibrate plate --prefix \"$UPM_PREFIX\" --config \"$UPM_CONFIG\" --out '{}'",
        exe.display(),
        staged.display()
    );
    let rig_s = ExciteParams::default().rig_seconds();
    let prefix = config.service.prefix.clone();
    let plan = crate::launcher::RunPlan {
        scenario: sc.name.clone(),
        seed,
        duration_s: rig_s + 30.0,
        config: config.clone(),
        planner_cmd: Some(client),
        planner_ends_run: true,
        vision_cmd: None,
        stress: false,
        camera: crate::launcher::CameraChoice::Truth,
        record: false,
        monitor: None,
        line: None,
        hmi: None,
    };
    let dir = std::path::Path::new("out/calibrate");
    let outcome = crate::launcher::run_plan(&plan, dir, true, &|_| serde_json::Value::Null);
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    outcome?;
    let log = dir.join("logs").join("planner.log");
    let cal = PlateCalibration::load(&staged).map_err(|_| {
        let said = std::fs::read_to_string(&log).unwrap_or_default();
        let last = said.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("no output").to_owned();
        anyhow::anyhow!("the calibration did not finish: {last} ({})", log.display())
    })?;
    let _ = std::fs::remove_file(&staged);
    let mut prev = staged.into_os_string();
    prev.push(".previous");
    let _ = std::fs::remove_file(prev);
    Ok(cal)
}

/// A few lines for the operator.
pub fn summary(c: &PlateCalibration) -> String {
    let r = &c.report;
    let classes: Vec<String> =
        c.class_friction.iter().map(|f| format!("class {}: {:.3}", f.class, f.scale)).collect();
    format!(
        "plate calibration: {} bursts, {:.0} s of rig time; {} observations used, {} rejected\n\
         turning: direction residual {:.2}° (median); friction: {} ; map {:?}\n\
         residual {:.1} % per observation; predicted force error {:.1} % (the fit's own uncertainty, median over the plate)",
        r.bursts,
        r.rig_seconds,
        r.observations,
        r.rejected,
        r.direction_residual_deg,
        classes.join(", "),
        c.friction_map.map(|x| (x * 1000.0).round() / 1000.0),
        100.0 * r.friction_residual,
        100.0 * r.predicted_force_err,
    )
}
