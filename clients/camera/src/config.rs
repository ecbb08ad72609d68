//! `[camera]` of the rig config: the rendered camera, in the file's units
//! (px, mm, degrees, ms), checked into a [`CameraModel`] and a [`Scene`].

use serde::{Deserialize, Serialize};
use upm_vision::class_outline::ClassOutline;
use upm_vision::lens::{CameraModel, Mount};

use crate::{ClassLook, Scene};

/// How one part class looks to the camera.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ClassSection {
    /// Reflectance in (0, 1].
    pub level: f64,
    /// Circumradius (a disc's radius).
    pub radius_mm: f64,
    #[serde(default)]
    pub shape: ClassOutline,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSection {
    pub width: u32,
    pub height: u32,
    pub focal_px: f64,
    /// Brown–Conrady k1, k2, p1, p2.
    pub distortion: [f64; 4],
    /// Lens centre over plate (x, y) and its height above the plate.
    pub mount_mm: [f64; 3],
    pub yaw_deg: f64,
    /// Tilt about the plate's x and y axes.
    pub tilt_deg: [f64; 2],
    pub frame_hz: f64,
    pub exposure_ms: f64,
    /// Sensor noise std, 8-bit levels.
    pub noise: f64,
    /// Illumination gain change per metre along plate x and y.
    pub gradient: [f64; 2],
    pub plate_level: f64,
    pub surround_level: f64,
    pub fiducial_mm: f64,
    pub seed: u64,
    /// The plate's half extent (m), as `[plate]` has it.
    pub half_extent: [f64; 2],
    pub classes: Vec<ClassSection>,
    /// The calibration board `upm calibrate camera` looks for.
    pub board: crate::board::Board,
}

impl Default for CameraSection {
    fn default() -> Self {
        Self {
            width: 2240,
            height: 1216,
            focal_px: 1560.0,
            distortion: [-0.06, 0.015, 0.0004, -0.0003],
            mount_mm: [4.0, -3.0, 1600.0],
            yaw_deg: 0.25,
            tilt_deg: [2.0, -1.5],
            frame_hz: rig_config::frame_rate::DEFAULT_FRAME_HZ,
            exposure_ms: 8.0,
            noise: 2.0,
            gradient: [0.12, -0.08],
            plate_level: 0.8,
            surround_level: 0.3,
            fiducial_mm: 60.0,
            seed: 1,
            half_extent: [1.0, 0.5],
            classes: vec![
                ClassSection { level: 0.1, radius_mm: 15.0, shape: ClassOutline::Disc },
                ClassSection { level: 0.4, radius_mm: 15.0, shape: ClassOutline::Disc },
            ],
            board: crate::board::Board::default(),
        }
    }
}

impl CameraSection {
    /// The camera as mounted; the message names the field.
    pub fn model(&self) -> Result<CameraModel, String> {
        if !(1..=8192).contains(&self.width) || !(1..=8192).contains(&self.height) {
            return Err(format!(
                "camera.width × height must be 1–8192 each, got {} × {}",
                self.width, self.height
            ));
        }
        if !(self.focal_px.is_finite() && self.focal_px > 0.0) {
            return Err(format!("camera.focal_px must be positive, got {}", self.focal_px));
        }
        if !(self.mount_mm[2].is_finite() && self.mount_mm[2] > 0.0) {
            return Err(format!("camera.mount_mm[2] (height) must be positive, got {}", self.mount_mm[2]));
        }
        let [x, y, h] = self.mount_mm.map(|v| v * 1e-3);
        let mount = Mount {
            x,
            y,
            height: h,
            yaw: self.yaw_deg.to_radians(),
            tilt_x: self.tilt_deg[0].to_radians(),
            tilt_y: self.tilt_deg[1].to_radians(),
        };
        let model = CameraModel::mounted(self.width, self.height, self.focal_px, self.distortion, mount);
        model.validate()?;
        Ok(model)
    }

    /// `[vision] classes` that see this camera's classes as they are.
    pub fn vision_classes(&self) -> Vec<upm_vision::VisionClass> {
        self.classes
            .iter()
            .map(|c| upm_vision::VisionClass {
                ratio: c.level / self.plate_level,
                radius_mm: c.radius_mm,
                shape: c.shape,
            })
            .collect()
    }

    /// The scene with the calibration board lying on the plate, no parts.
    pub fn board_scene(&self) -> Result<Scene, String> {
        Ok(Scene { board: Some(self.board), ..self.scene()? })
    }

    /// What the camera sees; the message names the field.
    pub fn scene(&self) -> Result<Scene, String> {
        if !(self.frame_hz.is_finite() && self.frame_hz > 0.0 && self.frame_hz <= 1000.0) {
            return Err(format!("camera.frame_hz must be in (0, 1000], got {}", self.frame_hz));
        }
        if !self.half_extent.iter().all(|h| h.is_finite() && *h > 0.0) {
            return Err("camera.half_extent must be positive".into());
        }
        let scene = Scene {
            plate_half_extent: self.half_extent,
            plate_level: self.plate_level,
            surround_level: self.surround_level,
            gradient: self.gradient,
            noise_sigma: self.noise,
            exposure_s: self.exposure_ms * 1e-3,
            classes: self
                .classes
                .iter()
                .map(|c| ClassLook { level: c.level, radius: c.radius_mm * 1e-3, shape: c.shape })
                .collect(),
            fiducial_side: self.fiducial_mm * 1e-3,
            seed: self.seed,
            board: None,
        };
        scene.validate()?;
        Ok(scene)
    }
}
