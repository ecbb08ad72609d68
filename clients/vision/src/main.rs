//! The camera client; all logic lives in the `upm_vision` library.

use clap::Parser;
use upm_vision::args::{VisionArgs, run_vision};

fn main() {
    match run_vision(VisionArgs::parse()) {
        Ok(frames) => eprintln!("upm-vision: stopped after {frames} frames"),
        Err(e) => {
            eprintln!("upm-vision: error: {}", format!("{e:#}").replace('\n', " "));
            std::process::exit(1);
        }
    }
}
