//! The operator page's process; all logic lives in the `upm_hmi` library.

use clap::Parser;
use upm_hmi::args::{HmiArgs, run_hmi_process};

fn main() {
    if let Err(e) = run_hmi_process(HmiArgs::parse()) {
        eprintln!("upm-hmi: error: {}", format!("{e:#}").replace('\n', " "));
        std::process::exit(1);
    }
}
