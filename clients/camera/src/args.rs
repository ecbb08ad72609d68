//! `upm-camera` command-line arguments and entry point.

use clap::Parser;
use rig_config::{ConfigError, ProcessArgs};

use crate::{CameraSection, Renderer};

#[derive(Debug, Parser)]
#[command(
    name = "upm-camera",
    version,
    about = "UPM frame source: the rendered camera (ground truth in), PNG files or a live camera; camera frames out"
)]
pub struct CameraArgs {
    /// `--config` is read for [service] and [camera] only.
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Publish the PNG files of this directory (name order) instead of
    /// rendering.
    #[arg(long)]
    pub files: Option<std::path::PathBuf>,
    /// A live USB/UVC camera through V4L2, e.g. /dev/video0, at
    /// camera.width × camera.height.
    #[arg(long, conflicts_with = "files")]
    pub v4l2: Option<std::path::PathBuf>,
    /// A live GenICam camera (GigE Vision / USB3 Vision) through Aravis, by
    /// its id as `arv-tool-0.8` lists it; "first" takes the first found.
    /// Needs the `genicam` build feature.
    #[arg(long, conflicts_with_all = ["files", "v4l2"])]
    pub genicam: Option<String>,
    /// With --files or a live camera: frames per second (default:
    /// camera.frame_hz).
    #[arg(long)]
    pub rate: Option<f64>,
    /// With --files: start over after the last file.
    #[arg(long = "loop")]
    pub looping: bool,
}

pub fn run_camera(args: CameraArgs) -> anyhow::Result<u64> {
    let file = args.process.file()?;
    let prefix = args.process.prefix(&file)?;
    let section = file.section::<CameraSection>("camera")?;
    let duration = args.process.duration().map_err(anyhow::Error::msg)?;
    if let Some(dir) = &args.files {
        let stats = crate::files::run_files(
            &prefix,
            dir,
            args.rate.unwrap_or(section.frame_hz),
            args.looping,
            duration,
        )?;
        eprintln!("upm-camera: {stats}");
        return Ok(stats.published);
    }
    let rate = args.rate.unwrap_or(section.frame_hz);
    let size = (section.width, section.height);
    if let Some(device) = &args.v4l2 {
        let stats = crate::live::v4l2(&prefix, device, size, rate, duration)?;
        eprintln!("upm-camera: {stats}");
        return Ok(stats.published);
    }
    if let Some(id) = &args.genicam {
        let stats = crate::live::genicam(&prefix, id, size, rate, duration)?;
        eprintln!("upm-camera: {stats}");
        return Ok(stats.published);
    }
    section.validate().map_err(|m| ConfigError::invalid(file.shown(), m))?;
    let renderer = Renderer::new(&section).map_err(anyhow::Error::msg)?;
    crate::run::run(&prefix, renderer, section.frame_hz, duration)
}
