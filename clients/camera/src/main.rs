//! The rendered camera; all logic lives in the `upm_camera` library.

use clap::Parser;
use upm_camera::args::{CameraArgs, run_camera};

fn main() {
    match run_camera(CameraArgs::parse()) {
        Ok(frames) => eprintln!("upm-camera: stopped after {frames} frames"),
        Err(e) => {
            eprintln!("upm-camera: error: {}", format!("{e:#}").replace('\n', " "));
            std::process::exit(1);
        }
    }
}
