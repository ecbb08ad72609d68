//! Play a solved schedule on the simulator and measure average forces/curls.

use anyhow::{Context, anyhow};
use drivers::rng::SplitMix64;
use drivers::{BodyShape, PartSpec, PartState, SimConfig, Simulator};
use upm_hardware::PlateState;
use upm_hardware::playback::play_estimating;
use upm_motion::{InertiaEstimate, PlateMotion, Rig};

use super::setup::ValidateSetup;
use crate::solve_json::SolveInput;
use upm_solver::PartShape;

// Every shape the solver accepts, the simulator can hold.
const _: () = assert!(upm_solver::MAX_SHAPE_VERTICES <= drivers::sim::MAX_POLYGON_VERTICES);

/// Radius of the disc used where a curl is measured (m).
pub const DISC_RADIUS: f64 = 0.05;
/// Start-position jitter per cycle (m), seeded.
const JITTER: f64 = 1e-4;
/// Averages over the cycles.
#[derive(Debug, Clone, Default)]
pub struct Measured {
    /// Per input part (in input order).
    pub forces: Vec<[f64; 2]>,
    /// The feed-forward's mass and inertia scale when the measured cycles
    /// ended (1 and 1 without adaptation).
    pub inertia_scale: [f64; 2],
    /// Std over cycles of each force component.
    pub force_std: Vec<[f64; 2]>,
    /// Per input curl constraint.
    pub curls: Vec<f64>,
    pub cycle_seconds: f64,
    pub force_saturated: u64,
    pub clamped: u64,
    pub fence_hits: u64,
}

/// Which body measures what.
struct Probe {
    position: [f64; 2],
    /// A point-model point where a curl is asked: a disc of DISC_RADIUS.
    disc: bool,
    /// A shaped part's own patch.
    patch: Option<PartShape>,
}

impl Probe {
    /// The simulator's body: a polygon as the simulator wants it (counter-
    /// clockwise about its centroid, placed at the centroid).
    fn spec(&self, mass: f64) -> PartSpec {
        let (shape, position) = match self.patch {
            Some(PartShape::Disc { radius }) => (BodyShape::Disc { radius }, self.position),
            Some(shape @ PartShape::Polygon { vertices, count }) => {
                let v = &vertices[..count];
                let g = shape.patch_points().centroid;
                // Clockwise input (negative signed area) is walked backwards.
                let twice_area: f64 = (0..count)
                    .map(|i| v[i][0] * v[(i + 1) % count][1] - v[(i + 1) % count][0] * v[i][1])
                    .sum();
                let mut out = [[0.0; 2]; drivers::sim::MAX_POLYGON_VERTICES];
                for (i, o) in out.iter_mut().take(count).enumerate() {
                    let src = if twice_area > 0.0 { v[i] } else { v[count - 1 - i] };
                    *o = [src[0] - g[0], src[1] - g[1]];
                }
                (
                    BodyShape::Polygon { vertices: out, count },
                    [self.position[0] + g[0], self.position[1] + g[1]],
                )
            }
            _ if self.disc => (BodyShape::Disc { radius: DISC_RADIUS }, self.position),
            _ => (BodyShape::Point { radius: 0.0 }, self.position),
        };
        PartSpec { shape, mass, position, angle: 0.0 }
    }
}

/// Simulate `cycles` cycles of the schedule (k per center, `order` play
/// order) and measure every constrained point of `input`, part `i`'s
/// material `part_friction[i]` times the nominal μ (a simulated plate's
/// truth, the plate's own friction map on top; empty: nominal).
pub fn measure(
    input: &SolveInput,
    k: &[f64],
    order: &[u16],
    cycles: usize,
    seed: u64,
    setup: &ValidateSetup,
    part_friction: &[f64],
) -> anyhow::Result<Measured> {
    if cycles == 0 {
        return Err(anyhow!("cycles: must be at least 1"));
    }
    let mut motion = PlateMotion::new(setup.motion).map_err(|e| anyhow!("{e}"))?;
    motion.set_from_solution(&input.centers, k, order).map_err(|e| anyhow!("schedule not playable: {e}"))?;
    let mut rig = Rig::new(setup.sim.rig).map_err(|e| anyhow!("{e}"))?;
    if let Some(m) = setup.twist_correction {
        rig = rig.with_correction(m);
    }
    rig.check_motion(&motion).map_err(|e| anyhow!("schedule beyond the actuators: {e}"))?;

    // One body per distinct point-model point (a curl there makes it a
    // disc of DISC_RADIUS); a shaped part is a body of its own shape.
    let mut probes: Vec<Probe> = Vec::new();
    let find =
        |probes: &[Probe], p: [f64; 2]| probes.iter().position(|q| q.position == p && q.patch.is_none());
    let mut part_body = Vec::new();
    for (n, p) in input.parts.iter().enumerate() {
        let shape = crate::solve_json::part_shape(p, n)?;
        let i = if shape == PartShape::Point {
            find(&probes, p.position).unwrap_or_else(|| {
                probes.push(Probe { position: p.position, disc: false, patch: None });
                probes.len() - 1
            })
        } else {
            probes.push(Probe { position: p.position, disc: false, patch: Some(shape) });
            probes.len() - 1
        };
        part_body.push(i);
    }
    // Top-level curls, then each part's own (the order of `curl_constraints`).
    let curl_points = input.curls.iter().map(|c| (c.position, None)).chain(
        input.parts.iter().enumerate().filter(|(_, p)| p.curl.is_some()).map(|(n, p)| (p.position, Some(n))),
    );
    let mut curl_body = Vec::new();
    for (position, part) in curl_points {
        let i = match part.map(|n| part_body[n]).filter(|&i| probes[i].patch.is_some()) {
            Some(i) => i,
            None => match find(&probes, position) {
                Some(i) => {
                    probes[i].disc = true;
                    i
                }
                None => {
                    probes.push(Probe { position, disc: true, patch: None });
                    probes.len() - 1
                }
            },
        };
        curl_body.push(i);
    }
    let mass = input.mu_m_g / (setup.sim.mu_kinetic * setup.sim.gravity);
    let specs: Vec<PartSpec> = probes.iter().map(|p| p.spec(mass)).collect();
    let cfg = SimConfig { tick_hz: setup.motion.tick_hz, seed, ..setup.sim };
    let mut sim = Simulator::new(cfg, &specs).map_err(|e| anyhow!("simulator: {e}"))?;
    for (&body, &s) in part_body.iter().zip(part_friction) {
        anyhow::ensure!(sim.set_part_friction(body, s), "part_friction: {s} refused (allowed 0.2..3)");
    }
    let mut rng = SplitMix64::new(seed ^ 0x005e_ed0f_u64);
    let t = motion.cycle_duration();
    let n = motion.cycle_ticks();
    let mut sum_f = vec![[0.0; 2]; probes.len()];
    let mut sum_f2 = vec![[0.0; 2]; probes.len()];
    let mut sum_tau = vec![0.0; probes.len()];
    let mut state = PlateState::default();
    let mut estimate = setup.inertia_warmup.map(|_| InertiaEstimate::new(setup.sim.drive_servo()));
    // One cycle from motion tick `c·n`; the estimate, if any, ends it.
    let mut play_cycle = |sim: &mut Simulator, c: u64| -> anyhow::Result<()> {
        play_estimating(sim, &rig, &motion, c * n, n, &mut state, estimate.as_mut())
            .context("simulator read")?;
        if let Some(e) = &mut estimate {
            rig.set_inertia_scale(e.end_cycle());
        }
        Ok(())
    };
    let warmup = setup.inertia_warmup.unwrap_or(0) as u64;
    for c in 0..warmup {
        play_cycle(&mut sim, c)?;
    }
    for c in warmup..warmup + cycles as u64 {
        for (i, p) in probes.iter().enumerate() {
            let (r, a) = (JITTER * rng.uniform().sqrt(), core::f64::consts::TAU * rng.uniform());
            let position = [p.position[0] + r * a.cos(), p.position[1] + r * a.sin()];
            sim.set_part(i, PartState { position, ..PartState::default() });
        }
        play_cycle(&mut sim, c)?;
        for (i, s) in (0..sim.part_count()).filter_map(|i| Some((i, sim.part(i)?))) {
            let f = [mass * s.velocity[0] / t, mass * s.velocity[1] / t];
            for d in 0..2 {
                sum_f[i][d] += f[d];
                sum_f2[i][d] += f[d] * f[d];
            }
            sum_tau[i] += sim.part_inertia(i).unwrap_or(0.0) * s.angular_velocity / t;
        }
    }
    let nc = cycles as f64;
    let mean = |i: usize| [sum_f[i][0] / nc, sum_f[i][1] / nc];
    let std = |i: usize| {
        let m = mean(i);
        [(sum_f2[i][0] / nc - m[0] * m[0]).max(0.0).sqrt(), (sum_f2[i][1] / nc - m[1] * m[1]).max(0.0).sqrt()]
    };
    let counters = sim.counters();
    Ok(Measured {
        forces: part_body.iter().map(|&i| mean(i)).collect(),
        inertia_scale: rig.inertia_scale(),
        force_std: part_body.iter().map(|&i| std(i)).collect(),
        // The curl whose torque this is: 2τ̄/ρ² with ρ² = I/m (4τ̄/a² for a
        // disc of radius a).
        curls: curl_body
            .iter()
            .map(|&i| 2.0 * (sum_tau[i] / nc) * mass / sim.part_inertia(i).unwrap_or(f64::NAN))
            .collect(),
        cycle_seconds: t,
        force_saturated: counters.force_saturated,
        clamped: counters.clamped,
        fence_hits: counters.fence_hits,
    })
}
