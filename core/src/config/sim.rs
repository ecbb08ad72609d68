//! `[sim]`: the physics simulator behind the core's default driver, and
//! the parts on its plate.

use drivers::{ActuatorModel, SimConfig};
use serde::{Deserialize, Serialize};
use upm_motion::RigParams;

use super::truth::TruthSection;

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SimSection {
    pub seed: u64,
    pub mu_static: f64,
    pub mu_kinetic: f64,
    /// "second_order" or "ideal".
    pub actuator: String,
    pub bandwidth_hz: f64,
    pub damping: f64,
    pub substeps: u32,
    /// Parts on the simulated plate (the simulated camera sees these).
    pub parts: Vec<SimPartSection>,
    /// How the plate really differs from the model (only the simulator
    /// reads it): a preset or a `[sim.truth]` table.
    pub truth: TruthSection,
}

/// One `[[sim.parts]]` entry.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimPartSection {
    pub id: u32,
    #[serde(default)]
    pub class: u32,
    /// "point", "disc", "square" or "triangle" (equilateral).
    pub shape: String,
    /// Disc radius or polygon side (m); a point's radius for contacts.
    pub size: f64,
    pub mass: f64,
    pub position: [f64; 2],
    #[serde(default)]
    pub angle: f64,
}

/// The simulator's parts with the ids and classes the camera reports.
#[derive(Debug, Clone, Default)]
pub struct SimParts {
    pub specs: Vec<drivers::PartSpec>,
    pub ids: Vec<u32>,
    pub classes: Vec<u32>,
    /// Each part's μ over the nominal (its class's in the truth).
    pub friction: Vec<f64>,
}

impl Default for SimSection {
    fn default() -> Self {
        let s = SimConfig::default();
        let (bandwidth_hz, damping) = match s.actuator {
            ActuatorModel::SecondOrder { bandwidth_hz, damping } => (bandwidth_hz, damping),
            ActuatorModel::Ideal => (1000.0, 0.7),
        };
        Self {
            seed: s.seed,
            mu_static: s.mu_static,
            mu_kinetic: s.mu_kinetic,
            actuator: "second_order".into(),
            bandwidth_hz,
            damping,
            substeps: s.substeps,
            parts: Vec::new(),
            truth: TruthSection::default(),
        }
    }
}

impl SimSection {
    /// The simulator's configuration for a rig ticking at `tick_hz` with a
    /// plate of `plate_half_extent`; the message names the field.
    pub fn config(&self, tick_hz: f64, plate_half_extent: [f64; 2]) -> Result<SimConfig, String> {
        let actuator = match self.actuator.as_str() {
            "second_order" => {
                ActuatorModel::SecondOrder { bandwidth_hz: self.bandwidth_hz, damping: self.damping }
            }
            "ideal" => ActuatorModel::Ideal,
            other => return Err(format!("sim.actuator {other:?}: expected \"second_order\" or \"ideal\"")),
        };
        let cfg = SimConfig {
            tick_hz,
            substeps: self.substeps,
            mu_static: self.mu_static,
            mu_kinetic: self.mu_kinetic,
            actuator,
            rig: RigParams::default(),
            plate_half_extent,
            seed: self.seed,
            truth: self.truth.resolve(RigParams::default().count, plate_half_extent)?.plate,
            ..SimConfig::default()
        };
        cfg.validate().map_err(|e| e.to_string())?;
        Ok(cfg)
    }

    /// `[[sim.parts]]` as simulator part specs (on a plate of
    /// `plate_half_extent`, with the truth's friction); ids must be unique.
    pub fn parts(&self, plate_half_extent: [f64; 2]) -> Result<SimParts, String> {
        let truth = self.truth.resolve(RigParams::default().count, plate_half_extent)?;
        let mut out = SimParts::default();
        for (i, p) in self.parts.iter().enumerate() {
            let field = format!("sim.parts[{i}]");
            if out.ids.contains(&p.id) {
                return Err(format!("{field}.id {} is used twice", p.id));
            }
            if !(p.size.is_finite() && p.size > 0.0) {
                return Err(format!("{field}.size must be finite and positive"));
            }
            let shape = match p.shape.as_str() {
                "point" => drivers::BodyShape::Point { radius: p.size },
                "disc" => drivers::BodyShape::Disc { radius: p.size },
                "square" => {
                    let h = 0.5 * p.size;
                    let mut vertices = [[0.0; 2]; drivers::sim::MAX_POLYGON_VERTICES];
                    vertices[..4].copy_from_slice(&[[-h, -h], [h, -h], [h, h], [-h, h]]);
                    drivers::BodyShape::Polygon { vertices, count: 4 }
                }
                "triangle" => {
                    // A vertex on the part's +x axis, as vision measures it.
                    let r = p.size / 3f64.sqrt();
                    let mut vertices = [[0.0; 2]; drivers::sim::MAX_POLYGON_VERTICES];
                    for (k, v) in vertices.iter_mut().take(3).enumerate() {
                        let a = k as f64 * core::f64::consts::TAU / 3.0;
                        *v = [r * a.cos(), r * a.sin()];
                    }
                    drivers::BodyShape::Polygon { vertices, count: 3 }
                }
                other => {
                    return Err(format!(
                        "{field}.shape {other:?}: expected \"point\", \"disc\", \"square\" or \"triangle\""
                    ));
                }
            };
            out.specs.push(drivers::PartSpec { shape, mass: p.mass, position: p.position, angle: p.angle });
            out.ids.push(p.id);
            out.classes.push(p.class);
            out.friction.push(truth.class_friction(p.class));
        }
        // The simulator checks mass, position and capacity; name the part.
        drivers::Simulator::new(SimConfig::default(), &out.specs).map_err(|e| format!("sim.parts: {e}"))?;
        Ok(out)
    }
}
