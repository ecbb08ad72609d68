//! `upm validate` (ARCHITECTURE.md §7): solve, then play the schedule on the
//! physics simulator and measure the forces and curls parts really feel.
//!
//! Each constrained point is a *free* body starting at rest at its position
//! (a point mass for force-only points, a disc of radius [`DISC_RADIUS`]
//! where a curl is asked); over one closed cycle its average friction force
//! is m·Δv/T and its average torque I·Δω/T, whose curl is 4τ̄/a². Every
//! cycle restarts the parts at rest (with a seeded ±0.1 mm position jitter)
//! while the plate keeps running through the default second-order actuator
//! model; the figures are averaged over `cycles`. Nothing assumes the answer:
//! friction comes from the relative velocity of plate and part only.

// Index loops mirror the matrix formulas; `!(x > 0.0)` deliberately rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

mod measure;
pub mod plot;
pub mod setup;

use std::path::Path;

use anyhow::Context;
use serde_json::json;

use crate::solve_json::{SolveInput, solve};

pub use measure::{DISC_RADIUS, Measured, measure};
pub use setup::{MEASURE_SUBSTEPS, ValidateSetup};

/// Solve `input`, simulate `cycles` cycles, and return the solve output plus
/// `simulated` (forces, curls, errors) as JSON. `plot` writes an SVG of the
/// average force field with parts and centers.
pub fn run(
    input: &SolveInput,
    cycles: usize,
    seed: u64,
    plot: Option<&Path>,
) -> anyhow::Result<serde_json::Value> {
    let out = solve(input)?;
    let order: Vec<u16> = out.order.iter().map(|&j| j as u16).collect();
    let setup = ValidateSetup::default();
    let m = measure(input, &out.k, &order, cycles, seed, &setup, &[])?;
    let mu_m_g = input.mu_m_g;
    let force_err: Vec<Option<f64>> = input
        .parts
        .iter()
        .zip(&m.forces)
        .map(|(p, s)| p.force.map(|f| (s[0] - f[0]).hypot(s[1] - f[1])))
        .collect();
    let force_ok: Vec<Option<bool>> = input
        .parts
        .iter()
        .zip(&force_err)
        .map(|(p, e)| p.force.zip(*e).map(|(f, e)| e <= 0.05 * f[0].hypot(f[1]) + 0.01 * mu_m_g))
        .collect();
    // Top-level curls, then each part's own, as `simulated.curls`.
    let asked: Vec<f64> =
        input.curls.iter().map(|c| c.curl).chain(input.parts.iter().filter_map(|p| p.curl)).collect();
    let curl_rel: Vec<f64> =
        asked.iter().zip(&m.curls).map(|(c, s)| ((s - c) / c.abs().max(1e-300)).abs()).collect();
    let curl_ok: Vec<bool> = asked
        .iter()
        .zip(&m.curls)
        .zip(&curl_rel)
        .map(|((c, s), r)| s.signum() == c.signum() && *r <= 0.15)
        .collect();
    let mut v = serde_json::to_value(&out)?;
    v["simulated"] = json!({
        "forces": m.forces,
        "curls": m.curls,
        "force_error": force_err,
        "force_error_over_mu_m_g": force_err.iter().map(|e| e.map(|e| e / mu_m_g)).collect::<Vec<_>>(),
        "force_within_target": force_ok,
        "curl_relative_error": curl_rel,
        "curl_within_target": curl_ok,
        "force_std": m.force_std,
        "cycles": cycles,
        "seed": seed,
        "cycle_seconds": m.cycle_seconds,
        "slot_ms": setup.motion.slot_duration() * 1e3,
        "displacement_mm": setup.motion.displacement * 1e3,
        "tick_hz": setup.motion.tick_hz,
        "disc_radius": DISC_RADIUS,
        "actuator": format!("{:?}", setup.sim.actuator_model()),
        "actuator_force_saturated_substeps": m.force_saturated,
        "clamped_commands": m.clamped,
        "fence_hits": m.fence_hits,
    });
    if let Some(path) = plot {
        plot::draw(path, input, &out.k, &m).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(v)
}
