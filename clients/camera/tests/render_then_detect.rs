//! The camera path end to end in one process: the rendered camera draws
//! known parts through a tilted, distorted lens; vision's segmentation and
//! detection find them again through the same calibration. Checked against
//! the renderer's truth: every part found once, of the right class, within
//! 0.1 mm; touching parts, parts cut by the plate's edge and bad frames are
//! counted, never reported as parts. Squares and triangles come out with
//! their angle (modulo their symmetry) within 0.5°.

use ipc_types::{PartState, PartStates};
use upm_camera::{CameraSection, ClassLook, Renderer};
use upm_vision::Detection;
use upm_vision::blobs::{BadFrame, SegmentParams, Segmenter};
use upm_vision::class_outline::ClassOutline;
use upm_vision::detect::{BlobCounts, detect, split_area_px};
use upm_vision::lens::CameraModel;
use upm_vision::part_look::PartLook;

/// A tilted, distorted camera over the 2 × 1 m plate, two disc classes.
fn scene() -> CameraSection {
    // The rig's default camera, turned and tilted less, with its own seed.
    CameraSection { yaw: 0.004, tilt: [0.035, -0.026], seed: 7, ..CameraSection::default() }
}

fn model() -> CameraModel {
    scene().model().expect("model")
}

struct Vision {
    segmenter: Segmenter,
    model: CameraModel,
    looks: Vec<PartLook>,
}

impl Vision {
    fn new() -> Self {
        Self::for_scene(&scene())
    }

    fn for_scene(scene: &CameraSection) -> Self {
        let m = model();
        let looks = scene.vision_classes();
        let params = SegmentParams { split_above_px: split_area_px(&m, &looks), ..SegmentParams::default() };
        Self { segmenter: Segmenter::new(&m, [1.0, 0.5], 0.003, params), model: m, looks }
    }

    fn see(&mut self, pixels: &[u8]) -> Result<(Vec<Detection>, BlobCounts), BadFrame> {
        let (w, h) = (self.model.width, self.model.height);
        let blobs = self.segmenter.segment(pixels, w, h, w as usize)?;
        let mut out = Vec::with_capacity(256);
        let mut counts = BlobCounts::default();
        detect(blobs, &self.model, &self.looks, &mut out, &mut counts);
        Ok((out, counts))
    }
}

#[test]
fn squares_and_triangles_are_found_with_their_angle_within_half_a_degree() {
    let polygons = CameraSection {
        classes: vec![
            // A 24 mm square and a 30 mm triangle (sides).
            ClassLook { level: 0.1, radius: 0.012 * 2f64.sqrt(), shape: ClassOutline::Square },
            ClassLook { level: 0.4, radius: 0.030 / 3f64.sqrt(), shape: ClassOutline::Triangle },
        ],
        ..scene()
    };
    let mut cam = Renderer::new(&polygons).expect("renderer");
    let mut vision = Vision::for_scene(&polygons);
    let mut truth = PartStates::new();
    let mut expected = Vec::new();
    for i in 0..24 {
        let (x, y) = (-0.85 + 0.075 * i as f64, if i % 2 == 0 { -0.3 } else { 0.25 });
        let theta = -3.0 + 0.27 * i as f64;
        let spin = if i % 4 == 1 { 2.0 } else { 0.0 };
        let class = i % 2;
        truth.push(PartState::new(i, class, 0, [x, y, theta], [0.02, 0.0, spin])).expect("capacity");
        expected.push((class, x, y, theta));
    }
    let (found, counts) = vision.see(cam.render(&truth)).expect("a good frame");
    assert_eq!(counts.detected, 24, "{counts:?}");
    let mut worst: f64 = 0.0;
    for (class, x, y, theta) in expected {
        let d = found.iter().find(|d| (d.x - x).hypot(d.y - y) < 0.01).expect("found");
        assert_eq!(d.class, class);
        let shape = polygons.classes[class as usize].shape;
        let err = shape.wrap(d.theta - theta).abs();
        assert!(d.theta.abs() <= shape.period() / 2.0 + 1e-9, "reported angle {} wraps", d.theta);
        worst = worst.max(err);
    }
    eprintln!("worst angle error {:.3}°", worst.to_degrees());
    // The target is 1° at p99; this scene does 0.2° at worst.
    assert!(worst < 0.5f64.to_radians(), "worst angle error {}°", worst.to_degrees());
}

fn states(parts: &[(u32, u32, [f64; 2], [f64; 2])]) -> PartStates {
    let mut m = PartStates::new();
    for &(id, class, [x, y], [vx, vy]) in parts {
        m.push(PartState::new(id, class, 0, [x, y, 0.0], [vx, vy, 0.0])).expect("capacity");
    }
    m
}

#[test]
fn separated_parts_are_found_within_a_tenth_of_a_millimetre() {
    let mut cam = Renderer::new(&scene()).expect("renderer");
    let mut vision = Vision::new();
    // Spread over the whole plate, corners included, some moving.
    let mut parts = Vec::new();
    let mut id = 0;
    for i in 0..8 {
        for j in 0..4 {
            let x = -0.9 + 0.257 * i as f64 + 0.013 * j as f64;
            let y = -0.40 + 0.27 * j as f64 - 0.008 * i as f64;
            let v = if (i + j) % 3 == 0 { [0.04, -0.02] } else { [0.0, 0.0] };
            parts.push((id, ((i + j) % 2) as u32, [x, y], v));
            id += 1;
        }
    }
    let truth = states(&parts);
    let mut errors = Vec::new();
    for _frame in 0..3 {
        let (found, counts) = vision.see(cam.render(&truth)).expect("a good frame");
        assert_eq!(counts, BlobCounts { detected: parts.len() as u64, ..BlobCounts::default() });
        for &(_, class, [x, y], _) in &parts {
            let near: Vec<_> = found.iter().filter(|d| (d.x - x).hypot(d.y - y) < 0.01).collect();
            assert_eq!(near.len(), 1, "part at ({x}, {y}): {near:?}");
            assert_eq!(near[0].class, class, "class of the part at ({x}, {y})");
            errors.push((near[0].x - x).hypot(near[0].y - y));
            if errors.last().is_some_and(|e| *e > 0.3e-3) {
                eprintln!("part at ({x:.3}, {y:.3}) seen at ({:.4}, {:.4})", near[0].x, near[0].y);
            }
        }
    }
    errors.sort_by(f64::total_cmp);
    let p99 = errors[(errors.len() * 99 / 100).min(errors.len() - 1)];
    eprintln!("position error p50 {:.3} mm, p99 {:.3} mm", errors[errors.len() / 2] * 1e3, p99 * 1e3);
    // The issue asks 0.3 mm; coverage-weighted centroids give ≈ 0.03 mm here.
    assert!(p99 < 0.1e-3, "position error p99 {} mm", p99 * 1e3);
}

#[test]
fn touching_pairs_are_split_clusters_and_cut_parts_counted() {
    let mut cam = Renderer::new(&scene()).expect("renderer");
    let mut vision = Vision::new();
    let pair = [(1, 0, [0.0, 0.0]), (2, 1, [0.0295, 0.004])];
    let truth = states(&[
        (pair[0].0, pair[0].1, pair[0].2, [0.0, 0.0]),
        (pair[1].0, pair[1].1, pair[1].2, [0.0, 0.0]), // touches part 1
        (3, 0, [0.4, 0.1], [0.0, 0.0]),                // three in a row
        (4, 0, [0.4295, 0.1], [0.0, 0.0]),
        (5, 1, [0.459, 0.1], [0.0, 0.0]),
        (6, 1, [0.995, 0.2], [0.0, 0.0]), // hangs over the plate's edge
        (7, 1, [-0.5, -0.2], [0.0, 0.0]), // alone
    ]);
    let (found, counts) = vision.see(cam.render(&truth)).expect("a good frame");
    assert_eq!(counts, BlobCounts { detected: 3, cut: 1, merged: 1, small: 0, split: 2 }, "{found:?}");
    // The pair comes out as its two parts, each of its own class.
    for (_, class, [x, y]) in pair {
        let d = found.iter().find(|d| (d.x - x).hypot(d.y - y) < 0.01).expect("found");
        assert_eq!(d.class, class, "{d:?}");
        assert!((d.x - x).hypot(d.y - y) < 1e-3, "{d:?} vs ({x}, {y})");
    }
    assert!(found.iter().any(|d| (d.x + 0.5).abs() < 1e-3 && (d.y + 0.2).abs() < 1e-3));
}

#[test]
fn bad_frames_are_named_and_give_no_parts() {
    let mut vision = Vision::new();
    let (w, h) = (model().width as usize, model().height as usize);
    assert_eq!(vision.see(&vec![0u8; w * h]).err(), Some(BadFrame::TooDark));
    assert_eq!(vision.see(&vec![255u8; w * h]).err(), Some(BadFrame::TooBright));
    assert_eq!(vision.see(&vec![128u8; w * h / 2]).err(), Some(BadFrame::WrongSize));
    // Salt and pepper everywhere: more dark runs than a frame of parts has.
    let noise: Vec<u8> = (0..w * h).map(|i| if (i * 7919) % 5 == 0 { 0 } else { 200 }).collect();
    assert_eq!(vision.see(&noise).err(), Some(BadFrame::TooManyRuns));
}
