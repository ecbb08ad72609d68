//! `upm-planner` command-line arguments and entry point.

use std::path::PathBuf;
use std::time::Duration;

use clap::Parser;

use super::run::run_planner;
use super::{PlannerParams, planner_by_name};
use crate::config::Config;
use crate::scenario::Scenario;

#[derive(Debug, Parser)]
#[command(name = "upm-planner", version, about = "UPM planner client (track, sort, spin, local)")]
pub struct PlannerArgs {
    /// Rig config (TOML): the service prefix and μmg.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// track, sort, spin or local.
    #[arg(long)]
    pub planner: String,
    /// Scenario file with the planner's parameters.
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    #[arg(long)]
    pub prefix: Option<String>,
    #[arg(long)]
    pub duration: Option<f64>,
}

pub fn run_planner_process(args: PlannerArgs) -> anyhow::Result<u64> {
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
