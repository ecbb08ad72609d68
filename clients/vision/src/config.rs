//! `[vision]` of the rig config, read straight into the type vision runs
//! on: where part poses come from (the simulator's ground truth through a
//! simulated camera, or camera frames through the image pipeline), the
//! simulated camera, the image pipeline and the tracker. Fields are SI;
//! the file's units (mm, degrees, ms) are in their serde attributes.

use serde::{Deserialize, Serialize};

use rig_config::frame_rate::{DEFAULT_FRAME_HZ, FRAMES_SOURCE};

use crate::blobs::SegmentParams;
use crate::class_outline::ClassOutline;
use crate::part_look::PartLook;

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
    /// The region searched is the plate shrunk by this (m).
    #[serde(rename = "roi_margin_mm", with = "upm_units::mm")]
    pub roi_margin: f64,
    /// Part classes as the camera sees them, for `"frames"`.
    pub classes: Vec<PartLook>,
    /// Frames a second of the simulated camera.
    pub frame_hz: f64,
    /// Std of the simulated camera's position noise (m) and angle noise (rad).
    #[serde(rename = "noise_mm", with = "upm_units::mm")]
    pub noise_m: f64,
    #[serde(rename = "noise_deg", with = "upm_units::deg")]
    pub noise_rad: f64,
    /// Frame stamp → published (s).
    #[serde(rename = "latency_ms", with = "upm_units::ms_as_s")]
    pub latency_s: f64,
    /// Probability a frame is lost.
    pub drop_probability: f64,
    pub seed: u64,
    /// The tracker's position gain (alpha-beta filter).
    pub alpha: f64,
    /// The tracker's velocity gain.
    pub beta: f64,
    /// Largest distance (m) between a track's prediction and its detection.
    #[serde(rename = "gate_mm", with = "upm_units::mm")]
    pub gate_m: f64,
    /// A track is dropped after this many frames unseen.
    pub max_missed_frames: u32,
}

impl Default for VisionSection {
    fn default() -> Self {
        let disc = |ratio| PartLook { ratio, radius: 0.015, shape: ClassOutline::Disc };
        Self {
            source: "truth".into(),
            calibration: String::new(),
            threshold: SegmentParams::default().threshold,
            roi_margin: 0.003,
            classes: vec![disc(0.125), disc(0.5)],
            frame_hz: DEFAULT_FRAME_HZ,
            noise_m: 0.0005,
            noise_rad: 0.005,
            latency_s: 0.0,
            drop_probability: 0.0,
            seed: 1,
            alpha: 0.5,
            beta: 0.1,
            gate_m: 0.05,
            max_missed_frames: 30,
        }
    }
}

impl VisionSection {
    /// Whether vision works from camera frames (else the ground truth).
    pub fn from_frames(&self) -> bool {
        self.source == FRAMES_SOURCE
    }

    /// Every field `source` uses; the message names the first bad one as
    /// the file spells it.
    pub fn validate(&self) -> Result<(), String> {
        let non_negative = |x: f64| x.is_finite() && x >= 0.0;
        if !(self.frame_hz.is_finite() && self.frame_hz > 0.0 && self.frame_hz <= 1000.0) {
            return Err(format!("vision.frame_hz must be in (0, 1000], got {}", self.frame_hz));
        }
        if !non_negative(self.noise_m) {
            return Err(format!("vision.noise_mm must be finite and >= 0, got {}", self.noise_m * 1e3));
        }
        if !non_negative(self.noise_rad) {
            return Err(format!(
                "vision.noise_deg must be finite and >= 0, got {}",
                self.noise_rad.to_degrees()
            ));
        }
        if !(non_negative(self.latency_s) && self.latency_s < 10.0) {
            return Err(format!("vision.latency_ms must be in [0, 10000), got {}", self.latency_s * 1e3));
        }
        if !(0.0..1.0).contains(&self.drop_probability) {
            return Err(format!("vision.drop_probability must be in [0, 1), got {}", self.drop_probability));
        }
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(format!("vision.alpha must be in (0, 1], got {}", self.alpha));
        }
        if !(self.beta > 0.0 && self.beta < 2.0) {
            return Err(format!("vision.beta must be in (0, 2), got {}", self.beta));
        }
        if !(self.gate_m.is_finite() && self.gate_m > 0.0) {
            return Err("vision.gate_mm must be positive".into());
        }
        match self.source.as_str() {
            "truth" => Ok(()),
            FRAMES_SOURCE if self.calibration.is_empty() => {
                Err("vision.calibration: a calibration file is needed with source = \"frames\"".into())
            }
            FRAMES_SOURCE => self.validate_frames(),
            other => Err(format!("vision.source {other:?}: expected \"truth\" or \"frames\"")),
        }
    }

    /// The image pipeline's fields whatever `source` says: an in-process
    /// camera gives vision its calibration itself.
    pub fn validate_frames(&self) -> Result<(), String> {
        if !(self.threshold.is_finite() && self.threshold > 0.0 && self.threshold < 1.0) {
            return Err(format!("vision.threshold must be in (0, 1), got {}", self.threshold));
        }
        if !(self.roi_margin.is_finite() && self.roi_margin >= 0.0) {
            return Err(format!("vision.roi_margin_mm must be >= 0, got {}", self.roi_margin * 1e3));
        }
        if self.classes.is_empty() {
            return Err("vision.classes: at least one part class is needed".into());
        }
        for (i, c) in self.classes.iter().enumerate() {
            c.validate().map_err(|m| format!("vision.classes[{i}].{m}"))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rig_config::RigFile;

    fn read(text: &str) -> Result<VisionSection, String> {
        let file = RigFile::parse(text, "t.toml").map_err(|e| e.to_string())?;
        let section = file.section::<VisionSection>("vision").map_err(|e| e.to_string())?;
        section.validate()?;
        Ok(section)
    }

    #[test]
    fn an_empty_table_is_the_default() {
        assert_eq!(read("[vision]\n").expect("valid"), VisionSection::default());
    }

    #[test]
    fn the_file_units_are_read_into_si() {
        let v = read(
            "[vision]\nnoise_mm = 0.5\nnoise_deg = 0.2864788975654116\nlatency_ms = 10.0\ngate_mm = 50.0\n\
             roi_margin_mm = 3.0\nclasses = [{ ratio = 0.125, radius_mm = 15.0 }, { ratio = 0.5, radius_mm = 15 }]\n",
        )
        .expect("valid");
        assert_eq!(v, VisionSection { latency_s: 0.01, ..VisionSection::default() });
    }

    #[test]
    fn a_bad_value_names_the_field_as_the_file_spells_it() {
        for (text, field) in [
            ("gate_mm = -1.0", "vision.gate_mm must be positive"),
            ("noise_mm = -1.0", "vision.noise_mm must be"),
            ("noise_deg = nan", "vision.noise_deg must be"),
            ("latency_ms = 1e5", "vision.latency_ms must be"),
            ("alpha = 0.0", "vision.alpha must be"),
            ("beta = 2.0", "vision.beta must be"),
            ("source = \"both\"", "vision.source \"both\""),
            ("source = \"frames\"", "vision.calibration:"),
            (
                "source = \"frames\"\ncalibration = \"c.toml\"\nroi_margin_mm = -1",
                "vision.roi_margin_mm must be",
            ),
            ("source = \"frames\"\ncalibration = \"c.toml\"\nthreshold = 1.0", "vision.threshold must be"),
            (
                "source = \"frames\"\ncalibration = \"c.toml\"\nclasses = [{ ratio = 0.5, radius_mm = 0.0 }]",
                "vision.classes[0].radius_mm must be",
            ),
            ("noise_mm = \"x\"", "vision.noise_mm: invalid type"),
            ("classes = [{ ratio = 0.5, radius = 0.01 }]", "vision.classes[0].radius: unknown field"),
        ] {
            let e = read(&format!("[vision]\n{text}\n")).expect_err(text);
            assert!(e.contains(field) && !e.contains('\n'), "{text}: {e}");
        }
    }
}
