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
}

pub fn run_vision(args: VisionArgs) -> anyhow::Result<u64> {
    let file = args.process.file()?;
    let prefix = args.process.prefix(&file)?;
    let (camera, tracker) = file
        .section::<VisionSection>("vision")?
        .params()
        .map_err(|m| ConfigError::invalid(file.shown(), m))?;
    let duration = args.process.duration().map_err(anyhow::Error::msg)?;
    crate::run(&prefix, camera, tracker, duration)
}
