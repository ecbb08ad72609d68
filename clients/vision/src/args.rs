//! `upm-vision` command-line arguments and entry point.

use clap::Parser;
use rig_config::{ConfigError, ProcessArgs};

use crate::VisionSection;

#[derive(Debug, Parser)]
#[command(name = "upm-vision", version, about = "UPM camera client (simulated camera by default)")]
pub struct VisionArgs {
    /// `--config` is read for [service] and [vision] only.
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Write what vision did with camera frames here (JSON) when it stops.
    #[arg(long)]
    pub stats: Option<std::path::PathBuf>,
}

pub fn run_vision(args: VisionArgs) -> anyhow::Result<u64> {
    let file = args.process.file()?;
    let prefix = args.process.prefix(&file)?;
    let section = file.section::<VisionSection>("vision")?;
    section.validate().map_err(|m| ConfigError::invalid(file.shown(), m))?;
    let duration = args.process.duration().map_err(anyhow::Error::msg)?;
    if !section.from_frames() {
        return crate::run(&prefix, &section, duration);
    }
    let stats = crate::frame_loop::run_frames(&prefix, &section, duration)?;
    eprintln!("upm-vision: {}", serde_json::to_string(&stats)?);
    if let Some(path) = &args.stats {
        std::fs::write(path, serde_json::to_string_pretty(&stats)?)
            .map_err(|e| anyhow::anyhow!("writing {}: {e}", path.display()))?;
    }
    Ok(stats.published)
}
