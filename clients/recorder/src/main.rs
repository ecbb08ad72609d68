//! The flight recorder process; all logic lives in the `upm_recorder` library.

use clap::Parser;
use upm_recorder::args::{RecorderArgs, run_recorder_process};

fn main() {
    if let Err(e) = run_recorder_process(RecorderArgs::parse()) {
        eprintln!("upm-recorder: error: {}", format!("{e:#}").replace('\n', " "));
        std::process::exit(1);
    }
}
