//! `[vision]` of the rig config: where part poses come from (the
//! simulator's ground truth through a simulated camera, or camera frames
//! through the image pipeline) and the tracker, in the file's units (mm,
//! degrees, ms), checked into [`CameraParams`], [`FrameParams`] and
//! [`TrackerParams`].

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::blobs::SegmentParams;
use crate::class_outline::ClassOutline;
use crate::detect::PartLook;
use crate::{Camera, CameraParams, TrackerParams};

/// How vision tells one part class from another in an image.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct VisionClass {
    /// Brightness relative to the plate, (0, 1).
    pub ratio: f64,
    /// Circumradius (a disc's radius).
    pub radius_mm: f64,
    #[serde(default)]
    pub shape: ClassOutline,
}

/// Vision from camera frames: what it needs besides the frames.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameParams {
    pub calibration: PathBuf,
    pub looks: Vec<PartLook>,
    pub segment: SegmentParams,
    /// The region searched is the plate shrunk by this (m).
    pub roi_margin: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct VisionSection {
    /// `"truth"`: the simulator's ground truth with noise (a fast test
    /// double, needs a core running the simulator); `"frames"`: camera
    /// frames from `upm/camera/frame`.
    pub source: String,
    /// Calibration file (TOML) for `"frames"`.
    pub calibration: String,
    /// Dark below this share of the local plate brightness.
    pub threshold: f64,
    pub roi_margin_mm: f64,
    /// Part classes as the camera sees them, for `"frames"`.
    pub classes: Vec<VisionClass>,
    pub frame_hz: f64,
    pub noise_mm: f64,
    pub noise_deg: f64,
    pub latency_ms: f64,
    pub drop_probability: f64,
    pub seed: u64,
    pub alpha: f64,
    pub beta: f64,
    pub gate_mm: f64,
    pub max_missed_frames: u32,
}

impl Default for VisionSection {
    fn default() -> Self {
        let c = CameraParams::default();
        let t = TrackerParams::default();
        Self {
            source: "truth".into(),
            calibration: String::new(),
            threshold: SegmentParams::default().threshold,
            roi_margin_mm: 3.0,
            classes: vec![
                VisionClass { ratio: 0.125, radius_mm: 15.0, shape: ClassOutline::Disc },
                VisionClass { ratio: 0.5, radius_mm: 15.0, shape: ClassOutline::Disc },
            ],
            frame_hz: c.frame_hz,
            noise_mm: c.noise_m * 1e3,
            noise_deg: c.noise_rad.to_degrees(),
            latency_ms: c.latency_s * 1e3,
            drop_probability: c.drop_probability,
            seed: c.seed,
            alpha: t.alpha,
            beta: t.beta,
            gate_mm: t.gate_m * 1e3,
            max_missed_frames: t.max_missed,
        }
    }
}

impl VisionSection {
    /// With `source = "frames"`, what the image pipeline needs; `None` for
    /// `"truth"`. The message names the field.
    pub fn frames(&self) -> Result<Option<FrameParams>, String> {
        match self.source.as_str() {
            "truth" => return Ok(None),
            rig_config::frame_rate::FRAMES_SOURCE => {}
            other => return Err(format!("vision.source {other:?}: expected \"truth\" or \"frames\"")),
        }
        if self.calibration.is_empty() {
            return Err("vision.calibration: a calibration file is needed with source = \"frames\"".into());
        }
        self.frames_for_camera().map(Some)
    }

    /// The image pipeline's settings whatever `source` says, the
    /// calibration given separately (an in-process camera).
    pub fn frames_for_camera(&self) -> Result<FrameParams, String> {
        if !(self.threshold.is_finite() && self.threshold > 0.0 && self.threshold < 1.0) {
            return Err(format!("vision.threshold must be in (0, 1), got {}", self.threshold));
        }
        if !(self.roi_margin_mm.is_finite() && self.roi_margin_mm >= 0.0) {
            return Err(format!("vision.roi_margin_mm must be >= 0, got {}", self.roi_margin_mm));
        }
        if self.classes.is_empty() {
            return Err("vision.classes: at least one part class is needed".into());
        }
        for (i, c) in self.classes.iter().enumerate() {
            if !(c.ratio.is_finite()
                && c.ratio > 0.0
                && c.ratio < 1.0
                && c.radius_mm.is_finite()
                && c.radius_mm > 0.0)
            {
                return Err(format!("vision.classes[{i}]: ratio in (0, 1) and radius_mm > 0 are needed"));
            }
        }
        Ok(FrameParams {
            calibration: PathBuf::from(&self.calibration),
            looks: self
                .classes
                .iter()
                .map(|c| PartLook { ratio: c.ratio, radius: c.radius_mm * 1e-3, shape: c.shape })
                .collect(),
            segment: SegmentParams { threshold: self.threshold, ..SegmentParams::default() },
            roi_margin: self.roi_margin_mm * 1e-3,
        })
    }

    /// Camera and tracker parameters; the message names the field.
    pub fn params(&self) -> Result<(CameraParams, TrackerParams), String> {
        let cam = CameraParams {
            frame_hz: self.frame_hz,
            noise_m: self.noise_mm * 1e-3,
            noise_rad: self.noise_deg.to_radians(),
            latency_s: self.latency_ms * 1e-3,
            drop_probability: self.drop_probability,
            seed: self.seed,
        };
        Camera::new(cam)?;
        if !(self.alpha > 0.0 && self.alpha <= 1.0 && self.beta > 0.0 && self.beta < 2.0) {
            return Err("vision: need 0 < alpha <= 1 and 0 < beta < 2".into());
        }
        if !(self.gate_mm.is_finite() && self.gate_mm > 0.0) {
            return Err("vision.gate_mm must be positive".into());
        }
        let tracker = TrackerParams {
            alpha: self.alpha,
            beta: self.beta,
            gate_m: self.gate_mm * 1e-3,
            max_missed: self.max_missed_frames,
        };
        Ok((cam, tracker))
    }
}
