//! `[sim]`: the physics simulator behind the core's default driver, and
//! the parts on its plate.

use core::fmt;

use drivers::SimConfig;
use serde::de::{MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use upm_motion::RigParams;

use super::truth::TruthSection;

/// `[sim]`: the simulator's settings, read straight into
/// `drivers::SimConfig`, and beside them the parts on its plate and how
/// the plate really differs from the model (only the simulator reads it).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SimSection {
    pub config: SimConfig,
    /// Parts on the simulated plate (the simulated camera sees these).
    pub parts: Vec<SimPartSection>,
    /// A preset or a `[sim.truth]` table.
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

impl SimParts {
    /// A feed cell's pool as the ground truth describes it: each part's
    /// class and outline (its id is the cell's, given as it arrives).
    pub fn of_pool(sim: &drivers::Simulator) -> Self {
        let mut out = Self::default();
        let Some(feed) = drivers::feed::FeedCell::of(sim) else { return out };
        for i in 0..sim.part_count() {
            out.specs.push(drivers::PartSpec {
                shape: feed.shape_of(i).unwrap_or(drivers::BodyShape::Point { radius: 0.0 }),
                mass: 0.0,
                position: [0.0; 2],
                angle: 0.0,
            });
            out.ids.push(0);
            out.classes.push(feed.class_of(i).unwrap_or(0));
            out.friction.push(1.0);
        }
        out
    }
}

impl<'de> Deserialize<'de> for SimSection {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = SimSection;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("the [sim] table")
            }
            fn visit_map<M: MapAccess<'de>>(self, m: M) -> Result<SimSection, M::Error> {
                let (mut parts, mut truth) = (Vec::new(), TruthSection::default());
                let config = rig_config::shared_table::read_shared(m, &["parts", "truth"], |key, m| {
                    match key {
                        "parts" => parts = m.next_value()?,
                        _ => truth = m.next_value()?,
                    }
                    Ok(())
                })?;
                Ok(SimSection { config, parts, truth })
            }
        }
        d.deserialize_map(V)
    }
}

impl Serialize for SimSection {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut table = rig_config::shared_table::write_rest(&self.config)?;
        let value = |v: Result<toml::Value, toml::ser::Error>| v.map_err(serde::ser::Error::custom);
        table.insert("parts".into(), value(toml::Value::try_from(&self.parts))?);
        table.insert("truth".into(), value(toml::Value::try_from(&self.truth))?);
        table.serialize(s)
    }
}

impl SimSection {
    /// The simulator's configuration for a rig ticking at `tick_hz` with a
    /// plate of `plate_half_extent`; the message names the field.
    pub fn config(&self, tick_hz: f64, plate_half_extent: [f64; 2]) -> Result<SimConfig, String> {
        let cfg = SimConfig {
            tick_hz,
            rig: RigParams::default(),
            plate_half_extent,
            truth: self.truth.resolve(RigParams::default().count, plate_half_extent)?.plate,
            ..self.config
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

#[cfg(test)]
mod tests {
    use crate::config::CoreConfig;

    #[test]
    fn the_simulators_settings_are_read_beside_its_parts_and_truth_and_errors_name_the_field() {
        let text = "[sim]\nseed = 9\nactuator = \"ideal\"\ntruth = \"worn\"\n\
                    [[sim.parts]]\nid = 4\nshape = \"disc\"\nsize = 0.01\nmass = 0.02\nposition = [0.1, 0.2]\n";
        let c: CoreConfig = CoreConfig::parse(text, "x.toml").expect("parses");
        assert_eq!((c.sim.config.seed, c.sim.config.actuator), (9, drivers::ActuatorKind::Ideal));
        assert_eq!((c.sim.parts.len(), c.sim.parts[0].id), (1, 4));
        assert_eq!(c.sim.config.mu_kinetic, drivers::SimConfig::default().mu_kinetic);
        let back: CoreConfig =
            CoreConfig::parse(&toml::to_string(&c).expect("prints"), "x.toml").expect("reads");
        assert_eq!(back.sim, c.sim);
        for (bad, field) in [
            ("[sim]\nseeds = 3", "sim.seeds: "),
            ("[sim]\nactuator = \"third_order\"", "actuator: unknown variant"),
            ("[sim]\nmu_static = \"high\"", "mu_static: invalid type"),
            ("[[sim.parts]]\nid = \"one\"", "sim.parts[0].id: "),
            ("[sim]\ntruth = 3", "sim.truth: "),
        ] {
            let e = CoreConfig::<toml::Table>::parse(bad, "x.toml").expect_err(bad).to_string();
            assert!(e.contains(field) && !e.contains('\n'), "{bad}: {e}");
        }
    }
}
