//! Each part's friction as a plate calibration found it: μ of a part of
//! class c at plate point (x, y) is μ·s_c·m(x, y), m = 1 + Σ c_k·term_k
//! over u = x / half-extent x, v = y / half-extent y and the terms u, v,
//! u·v, u² − ⅓, v² − ⅓ (the calibration file's model).
//!
//! The planner already divides each request by this scale, so the solver
//! never sees it; the part-dynamics correction does: a part that grips
//! harder is dragged further along within the cycle, and the force it
//! feels changes with that (`part_dynamics.rs`). Fixed capacity, `Copy`,
//! evaluated without allocation on the solver thread.

use core::fmt;

/// Part classes a calibration may name.
pub const MAX_FRICTION_CLASSES: usize = 16;
/// Terms of the friction map.
pub const FRICTION_MAP_TERMS: usize = 5;
/// A scale is kept within these wherever the part is (the map is
/// extrapolated off the plate).
pub const MIN_FRICTION_SCALE: f64 = 0.2;
pub const MAX_FRICTION_SCALE: f64 = 3.0;

/// Why a friction model was refused; each names its field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartFrictionError {
    TooManyClasses { count: usize },
    ClassScale { index: usize },
    MapTerm { term: usize },
    HalfExtent,
}

impl fmt::Display for PartFrictionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooManyClasses { count } => {
                write!(f, "class_friction: {count} classes, the core holds at most {MAX_FRICTION_CLASSES}")
            }
            Self::ClassScale { index } => write!(
                f,
                "class_friction[{index}].scale must be within {MIN_FRICTION_SCALE}..{MAX_FRICTION_SCALE}"
            ),
            Self::MapTerm { term } => write!(f, "friction_map[{term}] is not finite"),
            Self::HalfExtent => f.write_str("plate_half_extent must be finite and positive"),
        }
    }
}

impl core::error::Error for PartFrictionError {}

/// Per class scales and the map over the plate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartFriction {
    classes: [(u32, f64); MAX_FRICTION_CLASSES],
    count: usize,
    map: [f64; FRICTION_MAP_TERMS],
    half_extent: [f64; 2],
}

impl Default for PartFriction {
    /// Every part the model's friction.
    fn default() -> Self {
        Self::UNIFORM
    }
}

impl PartFriction {
    /// Every part the model's friction, everywhere.
    pub const UNIFORM: Self = Self {
        classes: [(0, 1.0); MAX_FRICTION_CLASSES],
        count: 0,
        map: [0.0; FRICTION_MAP_TERMS],
        half_extent: [1.0; 2],
    };

    /// `classes` as (class, scale); a class not named takes their mean.
    pub fn new(
        classes: &[(u32, f64)],
        map: [f64; FRICTION_MAP_TERMS],
        half_extent: [f64; 2],
    ) -> Result<Self, PartFrictionError> {
        if classes.len() > MAX_FRICTION_CLASSES {
            return Err(PartFrictionError::TooManyClasses { count: classes.len() });
        }
        if let Some(index) =
            classes.iter().position(|c| !(MIN_FRICTION_SCALE..=MAX_FRICTION_SCALE).contains(&c.1))
        {
            return Err(PartFrictionError::ClassScale { index });
        }
        if let Some(term) = map.iter().position(|c| !c.is_finite()) {
            return Err(PartFrictionError::MapTerm { term });
        }
        if !half_extent.iter().all(|h| h.is_finite() && *h > 0.0) {
            return Err(PartFrictionError::HalfExtent);
        }
        let mut out = Self { map, half_extent, count: classes.len(), ..Self::UNIFORM };
        out.classes[..classes.len()].copy_from_slice(classes);
        Ok(out)
    }

    /// True when every part has the model's friction everywhere.
    pub fn is_uniform(&self) -> bool {
        self.count == 0 && self.map.iter().all(|c| *c == 0.0)
    }

    /// μ of a part of `class` at (x, y) over the model's, within
    /// [`MIN_FRICTION_SCALE`, `MAX_FRICTION_SCALE`] (as the planner's
    /// `PlateCalibration::friction_scale`); 1 where that is not a number
    /// (the core's positions are validated finite and on the plate).
    pub fn scale(&self, class: u32, x: f64, y: f64) -> f64 {
        let named = &self.classes[..self.count];
        let s = match named.iter().find(|c| c.0 == class) {
            Some(c) => c.1,
            None if named.is_empty() => 1.0,
            None => named.iter().map(|c| c.1).sum::<f64>() / named.len() as f64,
        };
        let (u, v) = (x / self.half_extent[0], y / self.half_extent[1]);
        let terms = [u, v, u * v, u * u - 1.0 / 3.0, v * v - 1.0 / 3.0];
        let m = 1.0 + terms.iter().zip(&self.map).map(|(t, c)| t * c).sum::<f64>();
        let scale = s * m;
        if scale.is_nan() { 1.0 } else { scale.clamp(MIN_FRICTION_SCALE, MAX_FRICTION_SCALE) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_class_scales_the_map_and_an_unnamed_class_takes_the_mean() {
        let f =
            PartFriction::new(&[(0, 1.2), (3, 0.8)], [0.1, 0.0, 0.0, 0.15, 0.0], [1.0, 0.5]).expect("valid");
        let m = 1.0 + 0.1 * 0.5 + 0.15 * (0.25 - 1.0 / 3.0);
        assert!((f.scale(0, 0.5, 0.2) - 1.2 * m).abs() < 1e-15);
        assert!((f.scale(3, 0.5, 0.2) - 0.8 * m).abs() < 1e-15);
        assert!((f.scale(7, 0.5, 0.2) - 1.0 * m).abs() < 1e-15, "unnamed: the mean");
        assert_eq!(PartFriction::UNIFORM.scale(5, 0.3, -0.2), 1.0);
        assert!(PartFriction::UNIFORM.is_uniform() && !f.is_uniform());
        // Far off the plate the map is clamped; a non-finite place is 1.
        assert_eq!(f.scale(0, 1e9, 0.0), MAX_FRICTION_SCALE);
        assert_eq!(f.scale(0, f64::NAN, 0.0), 1.0);
    }

    #[test]
    fn bad_models_are_refused_naming_the_field() {
        let too_many = [(0, 1.0); MAX_FRICTION_CLASSES + 1];
        let cases = [
            (PartFriction::new(&too_many, [0.0; 5], [1.0; 2]), "class_friction: 17 classes"),
            (PartFriction::new(&[(0, 1.0), (1, f64::NAN)], [0.0; 5], [1.0; 2]), "class_friction[1].scale"),
            (PartFriction::new(&[], [0.0, 0.0, f64::INFINITY, 0.0, 0.0], [1.0; 2]), "friction_map[2]"),
            (PartFriction::new(&[], [0.0; 5], [0.0, 1.0]), "plate_half_extent"),
        ];
        for (r, want) in cases {
            let e = r.expect_err(want).to_string();
            assert!(e.starts_with(want), "{e}");
        }
    }
}
