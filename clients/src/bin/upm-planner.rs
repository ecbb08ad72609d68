//! The planner client; planners live in `upm_clients::planner`.

use std::path::PathBuf;
use std::time::Duration;

use clap::Parser;
use upm_clients::config::Config;
use upm_clients::planner::{PlannerParams, planner_by_name, run::run_planner};
use upm_clients::scenario::Scenario;

#[derive(Debug, Parser)]
#[command(name = "upm-planner", version, about = "UPM planner client (track, sort, spin, local)")]
struct Args {
    /// Rig config (TOML): the service prefix and μmg.
    #[arg(long)]
    config: Option<PathBuf>,
    /// track, sort, spin or local.
    #[arg(long)]
    planner: String,
    /// Scenario file with the planner's parameters.
    #[arg(long)]
    scenario: Option<PathBuf>,
    #[arg(long)]
    prefix: Option<String>,
    #[arg(long)]
    duration: Option<f64>,
}

fn run(args: Args) -> anyhow::Result<u64> {
    let config = match &args.config {
        Some(p) => Config::load(p)?,
        None => Config::default(),
    };
    let mut params = match &args.scenario {
        Some(s) => Scenario::load(s)?.planner_params(&config),
        None => PlannerParams {
            mu_m_g: config.plate.mu_m_g,
            mass: config.plate.mu_m_g / (config.sim.mu_kinetic * 9.81),
            ..PlannerParams::default()
        },
    };
    params.name = args.planner.clone();
    let mut planner = planner_by_name(&params)?;
    let prefix = args.prefix.unwrap_or(config.service.prefix.clone());
    let duration = args.duration.filter(|s| s.is_finite() && *s > 0.0).map(Duration::from_secs_f64);
    run_planner(planner.as_mut(), &prefix, duration)
}

fn main() {
    match run(Args::parse()) {
        Ok(n) => eprintln!("upm-planner: stopped after {n} requests"),
        Err(e) => {
            eprintln!("upm-planner: error: {}", format!("{e:#}").replace('\n', " "));
            std::process::exit(1);
        }
    }
}
