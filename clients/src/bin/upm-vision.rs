//! The camera client; all logic lives in `upm_clients::vision`.

use std::path::PathBuf;
use std::time::Duration;

use clap::Parser;
use upm_clients::config::Config;

#[derive(Debug, Parser)]
#[command(name = "upm-vision", version, about = "UPM camera client (simulated camera by default)")]
struct Args {
    /// Rig config (TOML): [service] prefix and [vision].
    #[arg(long)]
    config: Option<PathBuf>,
    /// Override service.prefix.
    #[arg(long)]
    prefix: Option<String>,
    /// Stop by itself after this many seconds.
    #[arg(long)]
    duration: Option<f64>,
}

fn run(args: Args) -> anyhow::Result<u64> {
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
    upm_clients::vision::run(&prefix, camera, tracker, duration)
}

fn main() {
    match run(Args::parse()) {
        Ok(frames) => eprintln!("upm-vision: stopped after {frames} frames"),
        Err(e) => {
            eprintln!("upm-vision: error: {}", format!("{e:#}").replace('\n', " "));
            std::process::exit(1);
        }
    }
}
