//! `[camera]` of the rig config, read straight into the type the rendered
//! camera runs on: the lens and its mount, the scene in front of it and
//! the sensor. Fields are SI; the file's units (mm, degrees, ms) are in
//! their serde attributes.

use serde::{Deserialize, Serialize};
use upm_vision::class_outline::ClassOutline;
use upm_vision::lens::CameraModel;
use upm_vision::part_look::PartLook;

use crate::board::Board;

/// How one part class looks to the camera (one of `[camera] classes`).
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ClassLook {
    /// Reflectance in (0, 1].
    pub level: f64,
    /// Circumradius (a disc's radius), m.
    #[serde(rename = "radius_mm", with = "upm_units::mm")]
    pub radius: f64,
    #[serde(default)]
    pub shape: ClassOutline,
}

impl ClassLook {
    /// The message names the field as the file spells it.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.level.is_finite() && self.level > 0.0 && self.level <= 1.0) {
            return Err(format!("level must be in (0, 1], got {}", self.level));
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(format!("radius_mm must be positive, got {}", self.radius * 1e3));
        }
        Ok(())
    }
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSection {
    pub width: u32,
    pub height: u32,
    pub focal_px: f64,
    /// Brown–Conrady k1, k2, p1, p2.
    pub distortion: [f64; 4],
    /// Lens centre over the plate (x, y) and its height above it (m).
    #[serde(rename = "mount_mm", with = "upm_units::mm")]
    pub mount: [f64; 3],
    /// Turn about the vertical (rad).
    #[serde(rename = "yaw_deg", with = "upm_units::deg")]
    pub yaw: f64,
    /// Tilt about the plate's x and y axes (rad).
    #[serde(rename = "tilt_deg", with = "upm_units::deg")]
    pub tilt: [f64; 2],
    pub frame_hz: f64,
    #[serde(rename = "exposure_ms", with = "upm_units::ms_as_s")]
    pub exposure_s: f64,
    /// Sensor noise std, 8-bit levels.
    pub noise: f64,
    /// Illumination gain change per metre along plate x and y.
    pub gradient: [f64; 2],
    /// Reflectance of the plate and of what lies beyond its edge.
    pub plate_level: f64,
    pub surround_level: f64,
    /// Side of a fiducial marker (m); markers sit just beyond the plate's
    /// corners and mid-edges.
    #[serde(rename = "fiducial_mm", with = "upm_units::mm")]
    pub fiducial_side: f64,
    pub seed: u64,
    /// The plate's half extent (m), as `[plate]` has it.
    pub half_extent: [f64; 2],
    pub classes: Vec<ClassLook>,
    /// The calibration board `upm calibrate camera` looks for.
    pub board: Board,
}

impl Default for CameraSection {
    fn default() -> Self {
        let disc = |level| ClassLook { level, radius: 0.015, shape: ClassOutline::Disc };
        Self {
            width: 2240,
            height: 1216,
            focal_px: 1560.0,
            distortion: [-0.06, 0.015, 0.0004, -0.0003],
            mount: [0.004, -0.003, 1.6],
            yaw: 0.25_f64.to_radians(),
            tilt: [2.0_f64.to_radians(), (-1.5_f64).to_radians()],
            frame_hz: rig_config::frame_rate::DEFAULT_FRAME_HZ,
            exposure_s: 0.008,
            noise: 2.0,
            gradient: [0.12, -0.08],
            plate_level: 0.8,
            surround_level: 0.3,
            fiducial_side: 0.06,
            seed: 1,
            half_extent: [1.0, 0.5],
            classes: vec![disc(0.1), disc(0.4)],
            board: Board::default(),
        }
    }
}

impl CameraSection {
    /// Every field; the message names the first bad one as the file
    /// spells it.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let level = |v: f64| v.is_finite() && v > 0.0 && v <= 1.0;
        if !(1..=8192).contains(&self.width) || !(1..=8192).contains(&self.height) {
            return Err(format!(
                "camera.width × height must be 1–8192 each, got {} × {}",
                self.width, self.height
            ));
        }
        if !(self.focal_px.is_finite() && self.focal_px > 0.0) {
            return Err(format!("camera.focal_px must be positive, got {}", self.focal_px));
        }
        if !finite(&self.distortion) {
            return Err("camera.distortion must be finite".into());
        }
        if !finite(&self.mount) {
            return Err("camera.mount_mm must be finite".into());
        }
        if self.mount[2] <= 0.0 {
            return Err(format!("camera.mount_mm[2] (height) must be positive, got {}", self.mount[2] * 1e3));
        }
        if !self.yaw.is_finite() {
            return Err("camera.yaw_deg must be finite".into());
        }
        if !finite(&self.tilt) {
            return Err("camera.tilt_deg must be finite".into());
        }
        if !(self.frame_hz.is_finite() && self.frame_hz > 0.0 && self.frame_hz <= 1000.0) {
            return Err(format!("camera.frame_hz must be in (0, 1000], got {}", self.frame_hz));
        }
        if !(self.exposure_s.is_finite() && (0.0..1.0).contains(&self.exposure_s)) {
            return Err(format!("camera.exposure_ms must be in [0, 1000), got {}", self.exposure_s * 1e3));
        }
        if !(self.noise.is_finite() && (0.0..=64.0).contains(&self.noise)) {
            return Err(format!("camera.noise must be in [0, 64] levels, got {}", self.noise));
        }
        if !(self.gradient.iter().all(|g| g.is_finite() && g.abs() <= 0.5)) {
            return Err("camera.gradient must be within ±0.5 per metre".into());
        }
        if !level(self.plate_level) {
            return Err(format!("camera.plate_level must be in (0, 1], got {}", self.plate_level));
        }
        if !level(self.surround_level) {
            return Err(format!("camera.surround_level must be in (0, 1], got {}", self.surround_level));
        }
        if !(self.fiducial_side.is_finite() && self.fiducial_side > 0.0) {
            return Err("camera.fiducial_mm must be positive".into());
        }
        if !self.half_extent.iter().all(|h| h.is_finite() && *h > 0.0) {
            return Err("camera.half_extent must be positive".into());
        }
        if self.classes.is_empty() {
            return Err("camera.classes: at least one part class is needed".into());
        }
        for (i, c) in self.classes.iter().enumerate() {
            c.validate().map_err(|m| format!("camera.classes[{i}].{m}"))?;
        }
        self.board.validate()
    }

    /// The camera as mounted, from a checked section.
    pub fn model(&self) -> Result<CameraModel, String> {
        self.validate()?;
        Ok(CameraModel::mounted(
            self.width,
            self.height,
            self.focal_px,
            self.distortion,
            self.mount,
            self.yaw,
            self.tilt,
        ))
    }

    /// `[vision] classes` that see this camera's classes as they are:
    /// brightness relative to the plate, outline and circumradius.
    pub fn vision_classes(&self) -> Vec<PartLook> {
        self.classes
            .iter()
            .map(|c| PartLook { ratio: c.level / self.plate_level, radius: c.radius, shape: c.shape })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rig_config::RigFile;

    fn read(text: &str) -> Result<CameraSection, String> {
        let file = RigFile::parse(text, "t.toml").map_err(|e| e.to_string())?;
        let section = file.section::<CameraSection>("camera").map_err(|e| e.to_string())?;
        section.validate()?;
        Ok(section)
    }

    #[test]
    fn an_empty_table_is_the_default() {
        assert_eq!(read("[camera]\n").expect("valid"), CameraSection::default());
    }

    #[test]
    fn the_file_units_are_read_into_si() {
        let c = read(
            "[camera]\nmount_mm = [4, -3.0, 1600.0]\nyaw_deg = 0.25\ntilt_deg = [2.0, -1.5]\nexposure_ms = 8\n\
             fiducial_mm = 60.0\nclasses = [{ level = 0.1, radius_mm = 15.0 }, { level = 0.4, radius_mm = 15 }]\n",
        )
        .expect("valid");
        assert_eq!(c, CameraSection::default());
        let d = CameraSection::default().model().expect("model");
        assert_eq!(c.model().expect("model"), d);
    }

    #[test]
    fn a_bad_value_names_the_field_as_the_file_spells_it() {
        for (text, field) in [
            ("width = 0", "camera.width × height"),
            ("focal_px = -1.0", "camera.focal_px must be"),
            ("distortion = [nan, 0.0, 0.0, 0.0]", "camera.distortion must be"),
            ("mount_mm = [0.0, 0.0, -5.0]", "camera.mount_mm[2] (height) must be positive, got -5"),
            ("mount_mm = [nan, 0.0, 1.0]", "camera.mount_mm must be finite"),
            ("yaw_deg = inf", "camera.yaw_deg must be"),
            ("frame_hz = 0.0", "camera.frame_hz must be"),
            ("exposure_ms = 1000.0", "camera.exposure_ms must be"),
            ("noise = 65.0", "camera.noise must be"),
            ("gradient = [0.6, 0.0]", "camera.gradient must be"),
            ("plate_level = 0.0", "camera.plate_level must be"),
            ("surround_level = 2.0", "camera.surround_level must be"),
            ("fiducial_mm = 0.0", "camera.fiducial_mm must be"),
            ("half_extent = [1.0, 0.0]", "camera.half_extent must be"),
            ("classes = []", "camera.classes: at least one"),
            ("classes = [{ level = 0.1, radius_mm = -1.0 }]", "camera.classes[0].radius_mm must be"),
            ("classes = [{ level = 1.5, radius_mm = 1.0 }]", "camera.classes[0].level must be"),
            ("exposure_ms = \"long\"", "camera.exposure_ms: invalid type"),
            ("tilt_deg = [1.0]", "camera.tilt_deg: invalid length"),
            ("mount = [0.0, 0.0, 1.6]", "unknown field `mount`"),
        ] {
            let e = read(&format!("[camera]\n{text}\n")).expect_err(text);
            assert!(e.contains(field) && !e.contains('\n'), "{text}: {e}");
        }
    }
}
