//! `[plate]` of the rig file: the plate's outline, the parts' friction
//! scale and the rotation centers.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlateParams {
    /// Half-extent of the plate outline (m), plate centered on its origin.
    pub half_extent: [f64; 2],
    /// μ·m·g of the parts (N): the scale of every requested force.
    pub mu_m_g: f64,
    /// Rotation centers (plate coordinates, m); schedules index into these.
    pub centers: Vec<[f64; 2]>,
}

impl Default for PlateParams {
    /// The paper's 2 m × 1 m plate with a center beyond each corner's side.
    fn default() -> Self {
        Self {
            half_extent: upm_motion::MotionParams::default().plate_half_extent,
            mu_m_g: 0.1,
            centers: vec![[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]],
        }
    }
}
