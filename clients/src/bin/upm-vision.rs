//! The camera client; all logic lives in `upm_clients::vision`.

use clap::Parser;
use upm_clients::vision::process::{VisionArgs, run_vision};

fn main() {
    match run_vision(VisionArgs::parse()) {
        Ok(frames) => eprintln!("upm-vision: stopped after {frames} frames"),
        Err(e) => {
            eprintln!("upm-vision: error: {}", format!("{e:#}").replace('\n', " "));
            std::process::exit(1);
        }
    }
}
