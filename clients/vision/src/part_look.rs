//! One part class as vision sees it (an entry of `[vision] classes`).

use serde::{Deserialize, Serialize};

use crate::class_outline::{BodyOutline, ClassOutline};

/// What vision knows about a part class (one of `[vision] classes`).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PartLook {
    /// Brightness relative to the plate, (0, 1).
    pub ratio: f64,
    /// Circumradius (a disc's radius), m.
    #[serde(rename = "radius_mm", with = "upm_units::mm")]
    pub radius: f64,
    #[serde(default)]
    pub shape: ClassOutline,
}

impl PartLook {
    /// The message names the field as the file spells it.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.ratio.is_finite() && self.ratio > 0.0 && self.ratio < 1.0) {
            return Err(format!("ratio must be in (0, 1), got {}", self.ratio));
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(format!("radius_mm must be positive, got {}", self.radius * 1e3));
        }
        Ok(())
    }

    pub fn area(&self) -> f64 {
        self.shape.area(self.radius)
    }

    /// The class's contact outline in a part's own frame.
    pub fn outline(&self) -> BodyOutline {
        self.shape.body_outline(self.radius)
    }
}
