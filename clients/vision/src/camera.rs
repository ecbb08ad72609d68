//! The simulated camera: samples the simulator's ground truth at a frame
//! rate, adds seeded noise, drops frames, and delays them by a latency.
//! Each part's outline passes through unchanged.

use std::collections::VecDeque;

use ipc_types::PartStates;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use crate::VisionSection;
use crate::class_outline::BodyOutline;
use crate::tracker::Detection;

/// A captured frame waiting for its latency to pass.
#[derive(Debug, Clone)]
pub struct Frame {
    pub stamp_ns: u64,
    pub detections: Vec<Detection>,
}

/// Runs on `[vision]`'s `frame_hz`, `noise_mm`, `noise_deg`, `latency_ms`,
/// `drop_probability` and `seed`.
#[derive(Debug)]
pub struct Camera {
    params: VisionSection,
    rng: ChaCha8Rng,
    pos: Normal<f64>,
    ang: Normal<f64>,
    queue: VecDeque<Frame>,
    pub dropped: u64,
}

impl Camera {
    /// Fails only for invalid parameters, with a message naming the field.
    pub fn new(params: &VisionSection) -> Result<Self, String> {
        params.validate()?;
        let normal = |s: f64| Normal::new(0.0, s).map_err(|e| format!("vision noise: {e}"));
        Ok(Self {
            rng: ChaCha8Rng::seed_from_u64(params.seed),
            pos: normal(params.noise_m)?,
            ang: normal(params.noise_rad)?,
            params: params.clone(),
            queue: VecDeque::new(),
            dropped: 0,
        })
    }

    pub fn params(&self) -> &VisionSection {
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
