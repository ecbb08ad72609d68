//! `upm-planner` command-line arguments and entry point.

use std::path::PathBuf;
use std::time::Duration;

use clap::Parser;
use rig_config::{ConfigError, RigFile, ServiceSection};

use crate::PlannerConfig;
use crate::run::run_planner;

#[derive(Debug, Parser)]
#[command(name = "upm-planner", version, about = "UPM planner client (track, sort, spin, local)")]
pub struct PlannerArgs {
    /// Rig config (TOML): [service] prefix and [planner] (name and parameters).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// track, sort, spin or local, with its default parameters when the
    /// config has no [planner]; must agree with planner.name when it has.
    #[arg(long)]
    pub planner: Option<String>,
    #[arg(long)]
    pub prefix: Option<String>,
    #[arg(long)]
    pub duration: Option<f64>,
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
    let file = RigFile::load_or_default(args.config.as_deref())?;
    let invalid = |m: String| ConfigError::invalid(file.shown(), m);
    let prefix =
        file.section::<ServiceSection>("service")?.prefix_or(args.prefix.as_deref()).map_err(invalid)?;
    let mut planner = planner_config(&file, args.planner.as_deref())?.build().map_err(invalid)?;
    let duration = match args.duration {
        Some(s) if s.is_finite() && s > 0.0 => Some(Duration::from_secs_f64(s)),
        Some(s) => anyhow::bail!("--duration must be a positive number of seconds, got {s}"),
        None => None,
    };
    run_planner(planner.as_mut(), &prefix, duration)
}
