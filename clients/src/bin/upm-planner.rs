//! The planner client; all logic lives in `upm_clients::planner`.

use clap::Parser;
use upm_clients::planner::process::{PlannerArgs, run_planner_process};

fn main() {
    match run_planner_process(PlannerArgs::parse()) {
        Ok(n) => eprintln!("upm-planner: stopped after {n} requests"),
        Err(e) => {
            eprintln!("upm-planner: error: {}", format!("{e:#}").replace('\n', " "));
            std::process::exit(1);
        }
    }
}
