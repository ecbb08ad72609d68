//! `upm-vision` command-line arguments and entry point.

use std::path::PathBuf;
use std::time::Duration;

use clap::Parser;

use crate::config::Config;

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
    let (config, shown) = match &args.config {
        Some(p) => (Config::load(p)?, p.display().to_string()),
        None => (Config::default(), "built-in defaults".into()),
    };
    let prefix = args.prefix.unwrap_or(config.service.prefix.clone());
    let (camera, tracker) = config.vision_params(&shown)?;
    let duration = match args.duration {
        Some(s) if s.is_finite() && s > 0.0 => Some(Duration::from_secs_f64(s)),
        Some(s) => anyhow::bail!("--duration must be a positive number of seconds, got {s}"),
        None => None,
    };
    super::run(&prefix, camera, tracker, duration)
}
