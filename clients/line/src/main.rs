//! The line process; all logic lives in the `upm_line` library.

use clap::Parser;
use upm_line::args::{LineArgs, run_line_process};

fn main() {
    if let Err(e) = run_line_process(LineArgs::parse()) {
        eprintln!("upm-line: error: {}", format!("{e:#}").replace('\n', " "));
        std::process::exit(1);
    }
}
