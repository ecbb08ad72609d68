//! The calibration file `upm-vision` loads when it works from camera
//! frames: the camera model and the plate's outline, as TOML. `upm
//! calibrate camera` writes it from the camera's view of the calibration
//! board (rendered, or PNG images of a real camera).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::lens::CameraModel;

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Calibration {
    /// The plate's half extent (m): the region vision looks for parts in.
    pub plate_half_extent: [f64; 2],
    pub camera: CameraModel,
}

impl Calibration {
    /// Read and check a calibration file; the error names the file and field.
    pub fn load(path: &Path) -> Result<Self, String> {
        let shown = path.display();
        let text = std::fs::read_to_string(path).map_err(|e| format!("calibration {shown}: {e}"))?;
        let cal: Self = toml::from_str(&text)
            .map_err(|e| format!("calibration {shown}: {}", e.to_string().replace('\n', " ")))?;
        cal.camera.validate().map_err(|m| format!("calibration {shown}: {m}"))?;
        if !cal.plate_half_extent.iter().all(|h| h.is_finite() && *h > 0.0) {
            return Err(format!("calibration {shown}: plate_half_extent must be positive"));
        }
        Ok(cal)
    }

    pub fn save(&self, path: &Path) -> Result<(), String> {
        let text = toml::to_string(self).map_err(|e| format!("calibration: {e}"))?;
        std::fs::write(path, text).map_err(|e| format!("writing {}: {e}", path.display()))
    }
}
