//! The recipe file's schema and its one check.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::RecipeError;
use crate::outline::Outline;

/// Friction of a class over the plate's nominal μ: what a simulated or
/// calibrated plate can hold.
const FRICTION_RANGE: core::ops::RangeInclusive<f64> = 0.2..=3.0;

/// `recipes/NAME.toml`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Recipe {
    pub name: String,
    /// `[[class]]`: the parts that arrive.
    #[serde(rename = "class")]
    pub classes: Vec<PartClass>,
    /// `[[pick]]`: where the robot takes a part of a class.
    #[serde(rename = "pick")]
    pub picks: Vec<PickPose>,
    pub infeed: Infeed,
    pub robot: Robot,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PartClass {
    pub id: u32,
    /// In the part's own frame (m).
    pub outline: Outline,
    /// This class's fraction of arrivals (shares are normalised).
    pub share: f64,
    /// The class's friction over the plate's nominal μ.
    #[serde(default = "one")]
    pub friction: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PickPose {
    pub class: u32,
    /// Plate coordinates (m).
    pub position: [f64; 2],
    /// rad.
    pub theta: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Infeed {
    pub rate_per_min: f64,
    /// `[x0, y0, x1, y1]` (m): where arrivals land.
    pub region: [f64; 4],
    pub max_on_plate: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Robot {
    /// The robot's cycle per part (s).
    pub pick_s: f64,
    /// How far a part may lie from its pick pose to be taken (m).
    #[serde(rename = "tolerance_mm", with = "upm_units::mm")]
    pub tolerance: f64,
    /// How far it may be turned from the pose's θ (rad).
    #[serde(rename = "tolerance_deg", with = "upm_units::deg")]
    pub tolerance_angle: f64,
    /// How long a part must have lain within tolerance (s).
    #[serde(default = "default_settle_s")]
    pub settle_s: f64,
    /// Room the gripper needs around a pick pose's part (m): no other part
    /// may reach into it.
    #[serde(rename = "clearance_mm", with = "upm_units::mm", default = "default_clearance")]
    pub clearance: f64,
}

fn one() -> f64 {
    1.0
}

fn default_settle_s() -> f64 {
    0.2
}

fn default_clearance() -> f64 {
    5e-3
}

impl Recipe {
    /// Read and check `path` for a plate of `plate_half_extent` (m).
    pub fn load(path: &Path, plate_half_extent: [f64; 2]) -> Result<Self, RecipeError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|source| RecipeError::Read { path: shown.clone(), source })?;
        Self::parse(&text, &shown, plate_half_extent)
    }

    /// Parse and check TOML text; `shown` names it in errors.
    pub fn parse(text: &str, shown: &str, plate_half_extent: [f64; 2]) -> Result<Self, RecipeError> {
        let invalid = |message: String| RecipeError::Invalid { path: shown.into(), message };
        let de = toml::Deserializer::parse(text).map_err(|e| invalid(one_line(&e.to_string())))?;
        let recipe: Self = serde_path_to_error::deserialize(de).map_err(|e| {
            let field = e.path().to_string();
            invalid(format!("{field}: {}", one_line(&e.into_inner().to_string())))
        })?;
        recipe.validate(plate_half_extent).map_err(invalid)?;
        Ok(recipe)
    }

    /// The box the pick poses span: lowest and highest x and y (m).
    pub fn pick_box(&self) -> ([f64; 2], [f64; 2]) {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for q in &self.picks {
            for k in 0..2 {
                (lo[k], hi[k]) = (lo[k].min(q.position[k]), hi[k].max(q.position[k]));
            }
        }
        (lo, hi)
    }

    /// The class `id`.
    pub fn class(&self, id: u32) -> Option<&PartClass> {
        self.classes.iter().find(|c| c.id == id)
    }

    /// Everything a cell needs to work; the message names the field.
    pub fn validate(&self, plate_half_extent: [f64; 2]) -> Result<(), String> {
        let [hx, hy] = plate_half_extent;
        if self.name.trim().is_empty() {
            return Err("name: must not be empty".into());
        }
        if self.classes.is_empty() {
            return Err("class: at least one [[class]] is needed".into());
        }
        for (i, c) in self.classes.iter().enumerate() {
            let field = format!("class[{i}]");
            if self.classes[..i].iter().any(|o| o.id == c.id) {
                return Err(format!("{field}.id: {} is used twice", c.id));
            }
            c.outline.check(hx.max(hy)).map_err(|e| format!("{field}.outline: {e}"))?;
            if !(c.share.is_finite() && c.share > 0.0) {
                return Err(format!("{field}.share: must be positive, got {}", c.share));
            }
            if !FRICTION_RANGE.contains(&c.friction) {
                return Err(format!("{field}.friction: must be in [0.2, 3], got {}", c.friction));
            }
        }
        for (i, p) in self.picks.iter().enumerate() {
            let field = format!("pick[{i}]");
            let Some(class) = self.class(p.class) else {
                return Err(format!("{field}.class: no [[class]] has id {}", p.class));
            };
            let reach = class.outline.reach();
            let on_plate = |v: f64, h: f64| v.is_finite() && v.abs() + reach <= h;
            if !(on_plate(p.position[0], hx) && on_plate(p.position[1], hy)) {
                return Err(format!(
                    "{field}.position: {:?} puts the part off the plate (±{hx}, ±{hy} m)",
                    p.position
                ));
            }
            if !p.theta.is_finite() {
                return Err(format!("{field}.theta: must be finite"));
            }
            for (j, q) in self.picks[..i].iter().enumerate() {
                let other = self.class(q.class).map_or(0.0, |c| c.outline.reach());
                let gap = (p.position[0] - q.position[0]).hypot(p.position[1] - q.position[1]);
                if gap < reach + other + self.robot.clearance {
                    return Err(format!(
                        "{field}.position: within pick[{j}]'s clearance ({:.1} mm apart, {:.1} mm needed)",
                        gap * 1e3,
                        (reach + other + self.robot.clearance) * 1e3
                    ));
                }
            }
        }
        if let Some(c) = self.classes.iter().find(|c| !self.picks.iter().any(|p| p.class == c.id)) {
            return Err(format!("pick: class {} has no pick pose", c.id));
        }
        let f = &self.infeed;
        if !(f.rate_per_min.is_finite() && f.rate_per_min > 0.0) {
            return Err(format!("infeed.rate_per_min: must be positive, got {}", f.rate_per_min));
        }
        let [x0, y0, x1, y1] = f.region;
        let inside = |v: f64, h: f64| v.is_finite() && v.abs() <= h;
        if !(inside(x0, hx) && inside(x1, hx) && inside(y0, hy) && inside(y1, hy) && x0 < x1 && y0 < y1) {
            return Err(format!(
                "infeed.region: {:?} must be x0 < x1, y0 < y1 on the plate (±{hx}, ±{hy} m)",
                f.region
            ));
        }
        let largest = self.classes.iter().map(|c| c.outline.reach()).fold(0.0, f64::max);
        if x1 - x0 < 2.0 * largest || y1 - y0 < 2.0 * largest {
            return Err("infeed.region: smaller than the largest part".into());
        }
        if !(1..=ipc_types::MAX_PARTS as u32).contains(&f.max_on_plate) {
            return Err(format!(
                "infeed.max_on_plate: must be in 1..={}, got {}",
                ipc_types::MAX_PARTS,
                f.max_on_plate
            ));
        }
        let r = &self.robot;
        let positive = |v: f64| v.is_finite() && v > 0.0;
        for (v, field) in
            [(r.pick_s, "pick_s"), (r.tolerance, "tolerance_mm"), (r.tolerance_angle, "tolerance_deg")]
        {
            if !positive(v) {
                return Err(format!("robot.{field}: must be positive"));
            }
        }
        if !(r.settle_s.is_finite() && r.settle_s >= 0.0) {
            return Err(format!("robot.settle_s: must be ≥ 0, got {}", r.settle_s));
        }
        if !(r.clearance.is_finite() && r.clearance >= 0.0) {
            return Err("robot.clearance_mm: must be ≥ 0".into());
        }
        Ok(())
    }
}

/// TOML's multi-line errors as one line.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
