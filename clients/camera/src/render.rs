//! The rendered camera: the simulator's ground truth drawn as a
//! machine-vision camera above the plate would see it, through the same
//! [`CameraModel`] that vision calibrates (tilted, distorted). What makes
//! it a camera and not a dot plotter: anti-aliased part edges (4 × 4
//! samples per pixel), motion blur from each part's velocity over the
//! exposure, an illumination gradient across the plate, seeded sensor noise,
//! a darker surround beyond the plate's edge, and fiducial markers at known
//! places around the plate. Classes differ in brightness (reflectance)
//! and may differ in outline (disc, square, triangle; polygons turn with
//! the part and blur with its spin too).
//!
//! Cost: the plate, surround, markers and lighting are drawn once; a frame
//! is a copy of that, the parts' bounding boxes, and the noise (a seeded
//! table read from a random offset). No allocation per frame.

use ipc_types::PartStates;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use upm_vision::lens::CameraModel;

use crate::{Board, CameraSection, ClassLook};

/// Sub-pixel sample offsets (4 × 4, in pixels from the centre).
const SUB: [f64; 4] = [-0.375, -0.125, 0.125, 0.375];
/// Noise table length beyond one frame: frames start at a random offset.
const NOISE_SLACK: usize = 1 << 16;
/// Time samples of a blurred part, at most.
const MAX_BLUR_SAMPLES: usize = 16;

#[derive(Debug)]
pub struct Renderer {
    model: CameraModel,
    camera: CameraSection,
    /// A calibration board lying on the plate (`upm calibrate camera`).
    board: Option<Board>,
    /// Plate point of every pixel centre (NaN where the ray misses).
    plate_xy: Vec<[f32; 2]>,
    /// The still scene, lit, without noise (levels 0–255).
    still: Vec<u8>,
    noise: Vec<i8>,
    rng: ChaCha8Rng,
    frame: Vec<u8>,
}

impl Renderer {
    /// The rig's camera looking at the plate and its parts. Precomputes
    /// the still scene and the noise table (allocates; slow for large
    /// sensors: about 0.1 s per megapixel).
    pub fn new(camera: &CameraSection) -> Result<Self, String> {
        Self::with_board(camera, None)
    }

    /// The same camera looking at its calibration board (`camera.board`)
    /// lying on the plate.
    pub fn board(camera: &CameraSection) -> Result<Self, String> {
        Self::with_board(camera, Some(camera.board))
    }

    fn with_board(camera: &CameraSection, board: Option<Board>) -> Result<Self, String> {
        let model = camera.model()?;
        let (w, h) = (model.width as usize, model.height as usize);
        let mut plate_xy = Vec::with_capacity(w * h);
        for v in 0..h {
            for u in 0..w {
                let p = model.unproject(u as f64, v as f64).map_or([f32::NAN; 2], |p| p.map(|c| c as f32));
                plate_xy.push(p);
            }
        }
        let mut rng = ChaCha8Rng::seed_from_u64(camera.seed);
        let normal = Normal::new(0.0, camera.noise).map_err(|e| format!("camera.noise: {e}"))?;
        let noise = (0..w * h + NOISE_SLACK)
            .map(|_| normal.sample(&mut rng).round().clamp(-127.0, 127.0) as i8)
            .collect();
        let mut r = Self {
            model,
            camera: camera.clone(),
            board,
            plate_xy,
            still: vec![0; w * h],
            noise,
            rng,
            frame: vec![0; w * h],
        };
        for v in 0..h {
            for u in 0..w {
                let i = v * w + u;
                let Some((p, ju, jv)) = r.pixel_frame(u, v) else { continue };
                let mut sum = 0.0;
                for su in SUB {
                    for sv in SUB {
                        let (x, y) = (p[0] + ju[0] * su + jv[0] * sv, p[1] + ju[1] * su + jv[1] * sv);
                        sum += r.still_level(x, y);
                    }
                }
                let level = sum / 16.0 * r.gain(p[0], p[1]);
                r.still[i] = (255.0 * level).round().clamp(0.0, 255.0) as u8;
            }
        }
        Ok(r)
    }

    pub fn model(&self) -> &CameraModel {
        &self.model
    }

    pub fn camera(&self) -> &CameraSection {
        &self.camera
    }

    /// Marker centres: beyond the plate's four corners and four mid-edges.
    pub fn fiducials(&self) -> [[f64; 2]; 8] {
        let m = 0.6 * self.camera.fiducial_side + 0.01;
        let [hx, hy] = self.camera.half_extent.map(|h| h + m);
        [[-hx, -hy], [0.0, -hy], [hx, -hy], [hx, 0.0], [hx, hy], [0.0, hy], [-hx, hy], [-hx, 0.0]]
    }

    /// Reflectance of the still scene (plate, surround, markers) at a point.
    fn still_level(&self, x: f64, y: f64) -> f64 {
        let c = &self.camera;
        let s = c.fiducial_side;
        for (i, [fx, fy]) in self.fiducials().into_iter().enumerate() {
            let (dx, dy) = (x - fx, y - fy);
            if dx.abs() <= s / 2.0 && dy.abs() <= s / 2.0 {
                // A black square with a white square off its centre; where
                // the white square sits tells the markers apart.
                let a = i as f64 * core::f64::consts::TAU / 8.0;
                let (wx, wy) = (fx + 0.22 * s * a.cos(), fy + 0.22 * s * a.sin());
                let inner = (x - wx).abs() <= 0.18 * s && (y - wy).abs() <= 0.18 * s;
                return if inner { 0.95 } else { 0.05 };
            }
        }
        if let Some(level) = self.board.as_ref().and_then(|b| b.level(x, y)) {
            return level;
        }
        let [hx, hy] = c.half_extent;
        if x.abs() <= hx && y.abs() <= hy { c.plate_level } else { c.surround_level }
    }

    fn gain(&self, x: f64, y: f64) -> f64 {
        let g = self.camera.gradient;
        (1.0 + g[0] * x + g[1] * y).max(0.05)
    }

    /// Plate point of pixel (u, v) and the plate offsets of one pixel step
    /// right and down.
    fn pixel_frame(&self, u: usize, v: usize) -> Option<([f64; 2], [f64; 2], [f64; 2])> {
        let (w, h) = (self.model.width as usize, self.model.height as usize);
        let at = |u: usize, v: usize| {
            let p = self.plate_xy[v * w + u];
            (p[0].is_finite() && p[1].is_finite()).then(|| [p[0] as f64, p[1] as f64])
        };
        let p = at(u, v)?;
        let (u2, su) = if u + 1 < w { (u + 1, 1.0) } else { (u - 1, -1.0) };
        let (v2, sv) = if v + 1 < h { (v + 1, 1.0) } else { (v - 1, -1.0) };
        let pu = at(u2, v)?;
        let pv = at(u, v2)?;
        Some((p, [(pu[0] - p[0]) * su, (pu[1] - p[1]) * su], [(pv[0] - p[0]) * sv, (pv[1] - p[1]) * sv]))
    }

    /// Draw one frame of `truth` (positions at the middle of the exposure).
    pub fn render(&mut self, truth: &PartStates) -> &[u8] {
        self.frame.copy_from_slice(&self.still);
        for p in truth.parts() {
            let classes = &self.camera.classes;
            let look = classes.get(p.class as usize).copied().unwrap_or(classes[0]);
            self.draw_part([p.x, p.y, p.theta], [p.vx, p.vy, p.omega], look);
        }
        let offset = self.rng.random_range(0..NOISE_SLACK);
        for (px, n) in self.frame.iter_mut().zip(&self.noise[offset..]) {
            *px = px.saturating_add_signed(*n);
        }
        &self.frame
    }

    /// One part at `pose` (x, y, θ) mid-exposure, moving at `velocity`.
    fn draw_part(&mut self, pose: [f64; 3], velocity: [f64; 3], look: ClassLook) {
        let centre = [pose[0], pose[1]];
        let Some(mpp) = self.model.metres_per_pixel(centre[0], centre[1]) else { return };
        let Some([cu, cv]) = self.model.project(centre[0], centre[1]) else { return };
        let e = self.camera.exposure_s;
        let travel = velocity[0].hypot(velocity[1]) * e;
        // Enough time samples that no edge point moves more than half a
        // pixel between two: translation plus the rim's travel in a spin.
        let sweep = travel + (velocity[2] * e).abs() * look.radius;
        let samples = ((2.0 * sweep / mpp).ceil() as usize).clamp(1, MAX_BLUR_SAMPLES);
        let reach = (look.radius + travel / 2.0) / mpp + 3.0;
        let (w, h) = (self.model.width as i64, self.model.height as i64);
        let (u0, u1) = (((cu - reach).floor() as i64).max(0), ((cu + reach).ceil() as i64).min(w - 1));
        let (v0, v1) = (((cv - reach).floor() as i64).max(0), ((cv + reach).ceil() as i64).min(h - 1));
        let inner = look.shape.inradius(look.radius);
        let start = [centre[0] - velocity[0] * e / 2.0, centre[1] - velocity[1] * e / 2.0];
        let step = if samples > 1 { e / (samples - 1) as f64 } else { 0.0 };
        let diag = 1.5 * mpp;
        let mut outlines = [look.shape.outline(look.radius, pose[2]); MAX_BLUR_SAMPLES];
        for (k, o) in outlines.iter_mut().enumerate().take(samples) {
            let t = if samples > 1 { k as f64 * step } else { e / 2.0 };
            *o = look.shape.outline(look.radius, pose[2] + velocity[2] * (t - e / 2.0));
        }
        for v in v0..=v1 {
            for u in u0..=u1 {
                let Some((p, ju, jv)) = self.pixel_frame(u as usize, v as usize) else { continue };
                // Whole pixel clearly outside every position of the disc.
                let (d_near, d_far) = segment_distances(p, start, [velocity[0], velocity[1]], e);
                if d_near > look.radius + diag {
                    continue;
                }
                let coverage = if d_far < inner - diag {
                    1.0
                } else {
                    let mut inside = 0u32;
                    for (k, outline) in outlines.iter().enumerate().take(samples) {
                        let t = if samples > 1 { k as f64 * step } else { e / 2.0 };
                        let c = [start[0] + velocity[0] * t, start[1] + velocity[1] * t];
                        for su in SUB {
                            for sv in SUB {
                                let dx = p[0] + ju[0] * su + jv[0] * sv - c[0];
                                let dy = p[1] + ju[1] * su + jv[1] * sv - c[1];
                                inside += u32::from(outline.contains(dx, dy));
                            }
                        }
                    }
                    inside as f64 / (16 * samples) as f64
                };
                if coverage > 0.0 {
                    let i = (v * w + u) as usize;
                    let part = 255.0 * look.level * self.gain(p[0], p[1]);
                    let value = self.frame[i] as f64 * (1.0 - coverage) + part * coverage;
                    self.frame[i] = value.round().clamp(0.0, 255.0) as u8;
                }
            }
        }
    }
}

/// Nearest and farthest distance from `p` to the segment a point travels
/// from `start` at `velocity` for `duration`.
fn segment_distances(p: [f64; 2], start: [f64; 2], velocity: [f64; 2], duration: f64) -> (f64, f64) {
    let end = [start[0] + velocity[0] * duration, start[1] + velocity[1] * duration];
    let (dx, dy) = (end[0] - start[0], end[1] - start[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - start[0]) * dx + (p[1] - start[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let near = (p[0] - start[0] - t * dx).hypot(p[1] - start[1] - t * dy);
    let far = (p[0] - start[0]).hypot(p[1] - start[1]).max((p[0] - end[0]).hypot(p[1] - end[1]));
    (near, far)
}
