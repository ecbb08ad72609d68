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
use upm_vision::class_outline::ClassOutline;
use upm_vision::detect::PartLook;
use upm_vision::lens::CameraModel;

/// How one part class looks: reflectance in (0, 1], outline and its
/// circumradius (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassLook {
    pub level: f64,
    pub radius: f64,
    pub shape: ClassOutline,
}

/// What is in front of the camera, and how the sensor sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub plate_half_extent: [f64; 2],
    /// Reflectance of the plate and of what lies beyond its edge.
    pub plate_level: f64,
    pub surround_level: f64,
    /// Illumination gain change per metre along plate x and y.
    pub gradient: [f64; 2],
    /// Sensor noise std, 8-bit levels.
    pub noise_sigma: f64,
    pub exposure_s: f64,
    pub classes: Vec<ClassLook>,
    /// Side of a fiducial marker (m); markers sit just beyond the plate's
    /// corners and mid-edges ([`Scene::fiducials`]).
    pub fiducial_side: f64,
    pub seed: u64,
    /// A calibration board lying on the plate (`upm calibrate camera`).
    pub board: Option<crate::board::Board>,
}

impl Scene {
    /// Marker centres: beyond the plate's four corners and four mid-edges.
    pub fn fiducials(&self) -> [[f64; 2]; 8] {
        let m = 0.6 * self.fiducial_side + 0.01;
        let (hx, hy) = (self.plate_half_extent[0] + m, self.plate_half_extent[1] + m);
        [[-hx, -hy], [0.0, -hy], [hx, -hy], [hx, 0.0], [hx, hy], [0.0, hy], [-hx, hy], [-hx, 0.0]]
    }

    /// How vision knows each class: brightness relative to the plate,
    /// outline and circumradius, as this scene draws them.
    pub fn part_looks(&self) -> Vec<PartLook> {
        self.classes
            .iter()
            .map(|c| PartLook { ratio: c.level / self.plate_level, radius: c.radius, shape: c.shape })
            .collect()
    }

    /// Reflectance of the still scene (plate, surround, markers) at a point.
    fn still_level(&self, x: f64, y: f64) -> f64 {
        let s = self.fiducial_side;
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
        let [hx, hy] = self.plate_half_extent;
        if x.abs() <= hx && y.abs() <= hy { self.plate_level } else { self.surround_level }
    }

    fn gain(&self, x: f64, y: f64) -> f64 {
        (1.0 + self.gradient[0] * x + self.gradient[1] * y).max(0.05)
    }

    /// One line naming the first field that makes no sense.
    pub fn validate(&self) -> Result<(), String> {
        let level = |v: f64| v.is_finite() && v > 0.0 && v <= 1.0;
        if !(level(self.plate_level) && level(self.surround_level)) {
            return Err("camera.plate_level and camera.surround_level must be in (0, 1]".into());
        }
        if self.classes.is_empty() {
            return Err("camera.classes: at least one part class is needed".into());
        }
        for (i, c) in self.classes.iter().enumerate() {
            if !(level(c.level) && c.radius.is_finite() && c.radius > 0.0) {
                return Err(format!("camera.classes[{i}]: level in (0, 1] and radius_mm > 0 are needed"));
            }
        }
        if !(self.noise_sigma.is_finite() && (0.0..=64.0).contains(&self.noise_sigma)) {
            return Err(format!("camera.noise must be in [0, 64] levels, got {}", self.noise_sigma));
        }
        if !(self.exposure_s.is_finite() && (0.0..1.0).contains(&self.exposure_s)) {
            return Err(format!("camera.exposure_ms must be in [0, 1000), got {}", self.exposure_s * 1e3));
        }
        if !(self.gradient.iter().all(|g| g.is_finite() && g.abs() <= 0.5)) {
            return Err("camera.gradient must be within ±0.5 per metre".into());
        }
        if !(self.fiducial_side.is_finite() && self.fiducial_side > 0.0) {
            return Err("camera.fiducial_mm must be positive".into());
        }
        if let Some(b) = &self.board {
            b.validate()?;
        }
        Ok(())
    }
}

/// Sub-pixel sample offsets (4 × 4, in pixels from the centre).
const SUB: [f64; 4] = [-0.375, -0.125, 0.125, 0.375];
/// Noise table length beyond one frame: frames start at a random offset.
const NOISE_SLACK: usize = 1 << 16;
/// Time samples of a blurred part, at most.
const MAX_BLUR_SAMPLES: usize = 16;

#[derive(Debug)]
pub struct Renderer {
    model: CameraModel,
    scene: Scene,
    /// Plate point of every pixel centre (NaN where the ray misses).
    plate_xy: Vec<[f32; 2]>,
    /// The still scene, lit, without noise (levels 0–255).
    still: Vec<u8>,
    noise: Vec<i8>,
    rng: ChaCha8Rng,
    frame: Vec<u8>,
}

impl Renderer {
    /// Precompute the still scene and the noise table (allocates; slow for
    /// large sensors: about 0.1 s per megapixel).
    pub fn new(model: CameraModel, scene: Scene) -> Result<Self, String> {
        model.validate()?;
        scene.validate()?;
        let (w, h) = (model.width as usize, model.height as usize);
        let mut plate_xy = Vec::with_capacity(w * h);
        for v in 0..h {
            for u in 0..w {
                let p = model.unproject(u as f64, v as f64).map_or([f32::NAN; 2], |p| p.map(|c| c as f32));
                plate_xy.push(p);
            }
        }
        let mut rng = ChaCha8Rng::seed_from_u64(scene.seed);
        let normal = Normal::new(0.0, scene.noise_sigma).map_err(|e| format!("camera.noise: {e}"))?;
        let noise = (0..w * h + NOISE_SLACK)
            .map(|_| normal.sample(&mut rng).round().clamp(-127.0, 127.0) as i8)
            .collect();
        let mut r = Self { model, scene, plate_xy, still: vec![0; w * h], noise, rng, frame: vec![0; w * h] };
        for v in 0..h {
            for u in 0..w {
                let i = v * w + u;
                let Some((p, ju, jv)) = r.pixel_frame(u, v) else { continue };
                let mut sum = 0.0;
                for su in SUB {
                    for sv in SUB {
                        let (x, y) = (p[0] + ju[0] * su + jv[0] * sv, p[1] + ju[1] * su + jv[1] * sv);
                        sum += r.scene.still_level(x, y);
                    }
                }
                let level = sum / 16.0 * r.scene.gain(p[0], p[1]);
                r.still[i] = (255.0 * level).round().clamp(0.0, 255.0) as u8;
            }
        }
        Ok(r)
    }

    pub fn model(&self) -> &CameraModel {
        &self.model
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
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
            let look = self.scene.classes.get(p.class as usize).copied().unwrap_or(self.scene.classes[0]);
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
        let e = self.scene.exposure_s;
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
                    let part = 255.0 * look.level * self.scene.gain(p[0], p[1]);
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
