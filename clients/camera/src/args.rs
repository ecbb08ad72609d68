//! `upm-camera` command-line arguments and entry point.

use clap::Parser;
use rig_config::{ConfigError, ProcessArgs};

use crate::{CameraSection, Renderer};

#[derive(Debug, Parser)]
#[command(name = "upm-camera", version, about = "UPM rendered camera: ground truth in, camera frames out")]
pub struct CameraArgs {
    /// `--config` is read for [service] and [camera] only.
    #[command(flatten)]
    pub process: ProcessArgs,
}

pub fn run_camera(args: CameraArgs) -> anyhow::Result<u64> {
    let file = args.process.file()?;
    let prefix = args.process.prefix(&file)?;
    let section = file.section::<CameraSection>("camera")?;
    let invalid = |m| ConfigError::invalid(file.shown(), m);
    let model = section.model().map_err(invalid)?;
    let scene = section.scene().map_err(invalid)?;
    let duration = args.process.duration().map_err(anyhow::Error::msg)?;
    let renderer = Renderer::new(model, scene).map_err(anyhow::Error::msg)?;
    crate::run::run(&prefix, renderer, section.frame_hz, duration)
}
