//! `upm-vision` command-line arguments and entry point.

use std::path::PathBuf;
use std::time::Duration;

use clap::Parser;

use rig_config::{ConfigError, RigFile, ServiceSection};

use crate::VisionSection;

#[derive(Debug, Parser)]
#[command(name = "upm-vision", version, about = "UPM camera client (simulated camera by default)")]
pub struct VisionArgs {
    /// Rig config (TOML): [service] prefix and [vision].
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Override service.prefix.
    #[arg(long)]
    pub prefix: Option<String>,
    /// Stop by itself after this many seconds.
    #[arg(long)]
    pub duration: Option<f64>,
}

pub fn run_vision(args: VisionArgs) -> anyhow::Result<u64> {
    let file = RigFile::load_or_default(args.config.as_deref())?;
    let invalid = |m: String| ConfigError::invalid(file.shown(), m);
    let prefix =
        file.section::<ServiceSection>("service")?.prefix_or(args.prefix.as_deref()).map_err(invalid)?;
    let (camera, tracker) = file.section::<VisionSection>("vision")?.params().map_err(invalid)?;
    let duration = match args.duration {
        Some(s) if s.is_finite() && s > 0.0 => Some(Duration::from_secs_f64(s)),
        Some(s) => anyhow::bail!("--duration must be a positive number of seconds, got {s}"),
        None => None,
    };
    crate::run(&prefix, camera, tracker, duration)
}
