//! `[sim] truth`: how the simulated plate really differs from the model
//! the controller runs on. Either a preset — `truth = "nominal"`, `"worn"`
//! or `"random:SEED"` — or a `[sim.truth]` table that starts from a preset
//! (`preset`, default nominal) and overrides what it names. Only the
//! simulator reads it (`drivers::PlateTruth`).

use core::fmt;

use drivers::{FRICTION_MAP_TERMS, FrictionMap, PlateTruth};
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use upm_hardware::MAX_ACTUATORS;

/// `[sim] truth`, as written.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum TruthSection {
    Preset(String),
    Table(TruthTable),
}

impl Default for TruthSection {
    fn default() -> Self {
        Self::Preset("nominal".into())
    }
}

/// `[sim.truth]`: a preset and the fields that override it.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TruthTable {
    pub preset: Option<String>,
    /// Per actuator, the attachment point's error (mm, plate frame).
    pub attach_offset_mm: Option<Vec<[f64; 2]>>,
    /// Per actuator, the push direction's error (mrad, counter-clockwise).
    pub direction_error_mrad: Option<Vec<f64>>,
    /// Per actuator, the position sensor's scale error (%).
    pub sensor_scale_error_pct: Option<Vec<f64>>,
    pub plate_mass_error_pct: Option<f64>,
    /// μ over the plate relative to nominal: coefficients of u, v, u·v,
    /// u² − ⅓, v² − ⅓ with u, v the position over the half-extents.
    pub friction_map: Option<[f64; FRICTION_MAP_TERMS]>,
    /// μ of each part class over the nominal, by class number (classes
    /// beyond the list keep the preset's).
    pub class_friction: Option<Vec<f64>>,
}

impl<'de> Deserialize<'de> for TruthSection {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = TruthSection;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"nominal\", \"worn\", \"random:SEED\" or a [sim.truth] table")
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<TruthSection, E> {
                Ok(TruthSection::Preset(s.to_owned()))
            }
            fn visit_map<M: MapAccess<'de>>(self, m: M) -> Result<TruthSection, M::Error> {
                TruthTable::deserialize(de::value::MapAccessDeserializer::new(m)).map(TruthSection::Table)
            }
        }
        d.deserialize_any(V)
    }
}

/// A preset by name.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Preset {
    Nominal,
    Worn,
    Random(u64),
}

impl Preset {
    fn parse(field: &str, s: &str) -> Result<Self, String> {
        match s {
            "nominal" => Ok(Self::Nominal),
            "worn" => Ok(Self::Worn),
            _ => match s.strip_prefix("random:").map(str::parse::<u64>) {
                Some(Ok(seed)) => Ok(Self::Random(seed)),
                _ => Err(format!("{field} {s:?}: expected \"nominal\", \"worn\" or \"random:SEED\"")),
            },
        }
    }

    fn truth(self, actuators: usize, half_extent: [f64; 2]) -> PlateTruth {
        match self {
            Self::Nominal => PlateTruth::NOMINAL,
            Self::Worn => PlateTruth::worn(),
            Self::Random(seed) => PlateTruth::random(seed, actuators, half_extent),
        }
    }

    fn class_friction(self, class: u32) -> f64 {
        match self {
            Self::Nominal => 1.0,
            Self::Worn => PlateTruth::worn_class_friction(class),
            Self::Random(seed) => PlateTruth::random_class_friction(seed, class),
        }
    }
}

/// The simulator's truth and each part class's friction scale.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedTruth {
    pub plate: PlateTruth,
    half_extent: [f64; 2],
    preset: Preset,
    class_friction: Vec<f64>,
}

impl ResolvedTruth {
    /// μ of part class `class` over the nominal.
    pub fn class_friction(&self, class: u32) -> f64 {
        self.class_friction.get(class as usize).copied().unwrap_or_else(|| self.preset.class_friction(class))
    }

    /// μ over the nominal felt by a part of `class` at plate point (x, y):
    /// its class's scale times the map there.
    pub fn friction_at(&self, class: u32, x: f64, y: f64) -> f64 {
        self.class_friction(class) * self.plate.friction_map.scale_at(self.half_extent, x, y)
    }
}

impl TruthSection {
    /// The truth for a rig of `actuators` actuators and a plate of
    /// `half_extent`; the message names the field.
    pub fn resolve(&self, actuators: usize, half_extent: [f64; 2]) -> Result<ResolvedTruth, String> {
        let (name, t) = match self {
            Self::Preset(s) => (s.as_str(), None),
            Self::Table(t) => (t.preset.as_deref().unwrap_or("nominal"), Some(t)),
        };
        let field = if t.is_some() { "sim.truth.preset" } else { "sim.truth" };
        let preset = Preset::parse(field, name)?;
        let mut plate = preset.truth(actuators, half_extent);
        let mut class_friction = Vec::new();
        if let Some(t) = t {
            let per_actuator = |name: &str, n: usize| {
                if n > actuators {
                    Err(format!("sim.truth.{name}: {n} entries for a rig of {actuators} actuators"))
                } else {
                    Ok(())
                }
            };
            if let Some(v) = &t.attach_offset_mm {
                per_actuator("attach_offset_mm", v.len())?;
                for (o, [x, y]) in plate.attach_offset.iter_mut().zip(v) {
                    *o = [x * 1e-3, y * 1e-3];
                }
            }
            if let Some(v) = &t.direction_error_mrad {
                per_actuator("direction_error_mrad", v.len())?;
                for (o, e) in plate.direction_error.iter_mut().zip(v) {
                    *o = e * 1e-3;
                }
            }
            if let Some(v) = &t.sensor_scale_error_pct {
                per_actuator("sensor_scale_error_pct", v.len())?;
                for (o, e) in plate.sensor_scale_error.iter_mut().zip(v) {
                    *o = e * 1e-2;
                }
            }
            if let Some(e) = t.plate_mass_error_pct {
                plate.plate_mass_error = e * 1e-2;
            }
            if let Some(c) = t.friction_map {
                plate.friction_map = FrictionMap { coefficients: c };
            }
            if let Some(c) = &t.class_friction {
                for (i, &s) in c.iter().enumerate() {
                    if !drivers::friction_scale_ok(s) {
                        return Err(format!(
                            "sim.truth.class_friction[{i}] = {s}: must be within {}..{}",
                            drivers::MIN_FRICTION_SCALE,
                            drivers::MAX_FRICTION_SCALE
                        ));
                    }
                }
                class_friction.clone_from(c);
            }
        }
        debug_assert!(actuators <= MAX_ACTUATORS);
        plate.validate(half_extent).map_err(|e| e.to_string())?;
        Ok(ResolvedTruth { plate, half_extent, preset, class_friction })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    struct Sim {
        #[serde(default)]
        truth: TruthSection,
    }

    fn resolve(text: &str) -> Result<ResolvedTruth, String> {
        let s: Sim = toml::from_str(text).map_err(|e| e.message().to_owned())?;
        s.truth.resolve(4, [1.0, 0.5])
    }

    #[test]
    fn presets_tables_and_their_errors() {
        assert_eq!(resolve("").expect("default").plate, PlateTruth::NOMINAL);
        assert_eq!(resolve("truth = \"worn\"").expect("worn").plate, PlateTruth::worn());
        let r = resolve("truth = \"random:7\"").expect("random");
        assert_eq!(r.plate, PlateTruth::random(7, 4, [1.0, 0.5]));
        assert_eq!(r.class_friction(3), PlateTruth::random_class_friction(7, 3));
        let t = resolve(
            "[truth]\npreset = \"worn\"\nsensor_scale_error_pct = [1, 2]\nclass_friction = [0.9]\nplate_mass_error_pct = -5",
        )
        .expect("table");
        assert_eq!(t.plate.sensor_scale_error[..3], [0.01, 0.02, PlateTruth::worn().sensor_scale_error[2]]);
        assert_eq!(t.plate.attach_offset, PlateTruth::worn().attach_offset);
        assert_eq!((t.class_friction(0), t.class_friction(1)), (0.9, 0.8));
        assert!((t.plate.plate_mass_error + 0.05).abs() < 1e-15);
        for (text, field) in [
            ("truth = \"shiny\"", "sim.truth \"shiny\""),
            ("truth = \"random:x\"", "sim.truth \"random:x\""),
            ("[truth]\npreset = \"old\"", "sim.truth.preset"),
            ("[truth]\nattach_offset_mm = [[0, 60]]", "sim.truth.attach_offset_mm[0]"),
            ("[truth]\ndirection_error_mrad = [0, 0, 0, 0, 1]", "sim.truth.direction_error_mrad: 5 entries"),
            ("[truth]\nclass_friction = [1, 0.1]", "sim.truth.class_friction[1]"),
            ("[truth]\nfriction_map = [0, 0, 0, 3, 0]", "sim.truth.friction_map spans"),
            ("[truth]\nplate_mass_error_pct = 300", "sim.truth.plate_mass_error_pct"),
        ] {
            let e = resolve(text).expect_err(text);
            assert!(e.starts_with(field), "{text}: {e}");
        }
        let e = resolve("[truth]\nbogus = 1").expect_err("unknown field");
        assert!(e.contains("bogus"), "{e}");
    }
}
