//! The simulated camera: samples the simulator's ground truth at a frame
//! rate, adds seeded noise, drops frames, and delays them by a latency.
//! Each part's outline passes through unchanged.

use std::collections::VecDeque;

use ipc_types::PartStates;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use crate::class_outline::BodyOutline;
use crate::tracker::Detection;

/// Tunables of the simulated camera (`[vision]` in the config).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraParams {
    pub frame_hz: f64,
    /// Std of position noise (m) and angle noise (rad).
    pub noise_m: f64,
    pub noise_rad: f64,
    /// Frame stamp → published (s).
    pub latency_s: f64,
    /// Probability a frame is lost.
    pub drop_probability: f64,
    pub seed: u64,
}

impl Default for CameraParams {
    fn default() -> Self {
        Self {
            frame_hz: rig_config::frame_rate::DEFAULT_FRAME_HZ,
            noise_m: 0.0005,
            noise_rad: 0.005,
            latency_s: 0.0,
            drop_probability: 0.0,
            seed: 1,
        }
    }
}

/// A captured frame waiting for its latency to pass.
#[derive(Debug, Clone)]
pub struct Frame {
    pub stamp_ns: u64,
    pub detections: Vec<Detection>,
}

#[derive(Debug)]
pub struct Camera {
    params: CameraParams,
    rng: ChaCha8Rng,
    pos: Normal<f64>,
    ang: Normal<f64>,
    queue: VecDeque<Frame>,
    pub dropped: u64,
}

impl Camera {
    /// Fails only for invalid parameters, with a message naming the field.
    pub fn new(params: CameraParams) -> Result<Self, String> {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if !(params.frame_hz.is_finite() && params.frame_hz > 0.0 && params.frame_hz <= 1000.0) {
            return Err(format!("vision.frame_hz must be in (0, 1000], got {}", params.frame_hz));
        }
        if !(ok(params.noise_m) && ok(params.noise_rad)) {
            return Err("vision.noise_m and vision.noise_rad must be finite and >= 0".into());
        }
        if !(ok(params.latency_s) && params.latency_s < 10.0) {
            return Err(format!("vision.latency_ms must be in [0, 10000), got {}", params.latency_s * 1e3));
        }
        if !(0.0..1.0).contains(&params.drop_probability) {
            return Err(format!(
                "vision.drop_probability must be in [0, 1), got {}",
                params.drop_probability
            ));
        }
        let normal = |s: f64| Normal::new(0.0, s).map_err(|e| format!("vision noise: {e}"));
        Ok(Self {
            params,
            rng: ChaCha8Rng::seed_from_u64(params.seed),
            pos: normal(params.noise_m)?,
            ang: normal(params.noise_rad)?,
            queue: VecDeque::new(),
            dropped: 0,
        })
    }

    pub fn params(&self) -> &CameraParams {
        &self.params
    }

    /// Capture the ground truth as one frame (or drop it).
    pub fn capture(&mut self, truth: &PartStates) {
        if self.params.drop_probability > 0.0 && self.rng.random::<f64>() < self.params.drop_probability {
            self.dropped += 1;
            return;
        }
        let detections = truth
            .parts()
            .iter()
            .map(|p| Detection {
                x: p.x + self.pos.sample(&mut self.rng),
                y: p.y + self.pos.sample(&mut self.rng),
                theta: p.theta + self.ang.sample(&mut self.rng),
                class: p.class,
                // The truth is unwrapped; so stays the estimate.
                period: 0.0,
                // The simulator's outline, as it is: noise moves the pose only.
                outline: BodyOutline::of(p),
            })
            .collect();
        self.queue.push_back(Frame { stamp_ns: truth.stamp_ns, detections });
    }

    /// The oldest frame whose latency has passed at `now_ns`.
    pub fn ready(&mut self, now_ns: u64) -> Option<Frame> {
        if self.next_ready_ns().is_some_and(|t| t <= now_ns) { self.queue.pop_front() } else { None }
    }

    /// When the oldest captured frame's latency passes (None: none waits).
    pub fn next_ready_ns(&self) -> Option<u64> {
        let latency_ns = (self.params.latency_s * 1e9) as u64;
        self.queue.front().map(|f| f.stamp_ns.saturating_add(latency_ns))
    }
}
