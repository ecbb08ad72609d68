//! The planner client; all logic lives in the `upm_planner` library.

use clap::Parser;
use upm_planner::args::{PlannerArgs, run_planner_process};

fn main() {
    match run_planner_process(PlannerArgs::parse()) {
        Ok(n) => eprintln!("upm-planner: stopped after {n} requests"),
        Err(e) => {
            eprintln!("upm-planner: error: {}", format!("{e:#}").replace('\n', " "));
            std::process::exit(1);
        }
    }
}
