//! `[vision]` of the rig config: the simulated camera and its tracker, in
//! the file's units (mm, degrees, ms), checked into [`CameraParams`] and
//! [`TrackerParams`].

use serde::{Deserialize, Serialize};

use crate::{Camera, CameraParams, TrackerParams};

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct VisionSection {
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
