//! `upm-planner` command-line arguments and entry point.

use clap::Parser;
use rig_config::{ConfigError, ProcessArgs, RigFile};

use crate::PlannerConfig;
use crate::run::run_planner;

#[derive(Debug, Parser)]
#[command(name = "upm-planner", version, about = "UPM planner client (track, sort, sort_paper, spin, local)")]
pub struct PlannerArgs {
    /// `--config` is read for [service], [planner] (name and parameters)
    /// and [calibration] (the plate calibration file) only.
    #[command(flatten)]
    pub process: ProcessArgs,
    /// track, sort, sort_paper, spin or local, with its default parameters when the
    /// config has no [planner]; must agree with planner.name when it has.
    #[arg(long)]
    pub planner: Option<String>,
    /// At exit, write what the planner learnt (JSON) here.
    #[arg(long)]
    pub stats: Option<std::path::PathBuf>,
}

/// The planner the config and `--planner` ask for.
pub fn planner_config(file: &RigFile, name: Option<&str>) -> Result<PlannerConfig, ConfigError> {
    let invalid = |m: String| ConfigError::invalid(file.shown(), m);
    let from_file = file.section::<Option<PlannerConfig>>("planner")?;
    match (from_file, name) {
        (Some(c), Some(n)) if c.name() != n => {
            Err(invalid(format!("--planner {n} disagrees with planner.name = {:?}", c.name())))
        }
        (Some(c), _) => Ok(c),
        (None, Some(n)) => PlannerConfig::by_name(n).map_err(invalid),
        (None, None) => Ok(PlannerConfig::default()),
    }
}

pub fn run_planner_process(args: PlannerArgs) -> anyhow::Result<u64> {
    let file = args.process.file()?;
    let prefix = args.process.prefix(&file)?;
    let config = planner_config(&file, args.planner.as_deref())?;
    let calibration = file.section::<Option<rig_config::CalibrationSection>>("calibration")?;
    let calibration = match calibration.and_then(|c| c.file) {
        Some(path) => {
            let c = rig_config::PlateCalibration::load(&path)
                .map_err(|m| ConfigError::invalid(file.shown(), m))?;
            eprintln!("upm-planner: friction from {}", path.display());
            Some(c)
        }
        None => None,
    };
    let mut planner = crate::calibrated::on_plate(&config, calibration)
        .map_err(|m| ConfigError::invalid(file.shown(), m))?;
    let duration = args.process.duration().map_err(anyhow::Error::msg)?;
    let sent = run_planner(planner.as_mut(), &prefix, duration)?;
    if let Some(path) = &args.stats {
        let estimates: Vec<String> = planner
            .friction_estimates()
            .iter()
            .map(|(id, s)| format!("{{\"id\": {id}, \"friction_scale\": {s}}}"))
            .collect();
        let windows = planner.learning_counts().map_or("null".into(), |c| {
            format!(
                "{{\"updates\": {}, \"skipped\": {}, \"rejected\": {}}}",
                c.updates, c.skipped, c.rejected
            )
        });
        let text = format!(
            "{{\"requests\": {sent}, \"friction_estimates\": [{}], \"learning_windows\": {windows}}}\n",
            estimates.join(", ")
        );
        std::fs::write(path, text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    }
    Ok(sent)
}
