//! `upm calibrate camera`: the camera model vision needs, from images of
//! the calibration board (`[camera.board]`, a Kalibr AprilGrid lying on the
//! plate) — rendered by the rig's `[camera]` (whose true parameters stay
//! hidden from the fit, and are compared with it afterwards) or read from
//! PNG files of a real camera.
//!
//! The board's tags are found by the `aprilgrid` crate; each tag's centre
//! (the mean of its four corners) is matched to its plate position. The
//! fit is Levenberg–Marquardt over focal length, radial k1 k2, tangential
//! p1 p2 and the camera's pose (rotation vector, translation), the
//! principal point held at the image centre, started from the homography
//! of the centres. One planar view leaves focal length and height nearly
//! interchangeable; the plate ↔ pixel mapping, which is all vision uses,
//! is what the fit pins down and what is reported.

use std::path::Path;

use aprilgrid::TagFamily;
use aprilgrid::detector::TagDetector;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use serde_json::{Value, json};
use upm_camera::{Board, CameraSection, Renderer};
use upm_vision::calibration::Calibration;
use upm_vision::lens::CameraModel;

/// One tag seen: where it lies on the plate and where its centre is in
/// the image (px).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seen {
    pub id: u32,
    pub plate: [f64; 2],
    pub pixel: [f64; 2],
}

/// The board's tags in one mono8 image.
pub fn detect_board(img: image::GrayImage, board: &Board) -> Vec<Seen> {
    let tags = TagDetector::new(&TagFamily::T36H11, None).detect(&image::DynamicImage::ImageLuma8(img));
    let mut seen: Vec<Seen> = tags
        .iter()
        .filter_map(|(&id, corners)| {
            let plate = board.tag_centre(id as usize)?;
            let [u, v] =
                corners.iter().fold([0.0, 0.0], |a, c| [a[0] + c.0 as f64 / 4.0, a[1] + c.1 as f64 / 4.0]);
            Some(Seen { id, plate, pixel: [u, v] })
        })
        .collect();
    seen.sort_by_key(|s| s.id);
    seen
}

const PARAMS: usize = 11;

fn rodrigues(r: [f64; 3]) -> Matrix3<f64> {
    let v = Vector3::from(r);
    let angle = v.norm();
    if angle < 1e-12 {
        return Matrix3::identity();
    }
    let k = v / angle;
    let kx = Matrix3::new(0.0, -k.z, k.y, k.z, 0.0, -k.x, -k.y, k.x, 0.0);
    Matrix3::identity() + kx * angle.sin() + kx * kx * (1.0 - angle.cos())
}

fn rotation_vector(r: &Matrix3<f64>) -> [f64; 3] {
    let angle = ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
    if angle < 1e-12 {
        return [0.0; 3];
    }
    let s = 2.0 * angle.sin();
    [
        (r[(2, 1)] - r[(1, 2)]) / s * angle,
        (r[(0, 2)] - r[(2, 0)]) / s * angle,
        (r[(1, 0)] - r[(0, 1)]) / s * angle,
    ]
}

fn model(p: &DVector<f64>, width: u32, height: u32) -> CameraModel {
    let r = rodrigues([p[5], p[6], p[7]]);
    CameraModel {
        width,
        height,
        fx: p[0],
        fy: p[0],
        cx: (width as f64 - 1.0) / 2.0,
        cy: (height as f64 - 1.0) / 2.0,
        k1: p[1],
        k2: p[2],
        p1: p[3],
        p2: p[4],
        rotation: [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]),
        translation: [p[8], p[9], p[10]],
    }
}

fn residuals(p: &DVector<f64>, seen: &[Seen], width: u32, height: u32) -> DVector<f64> {
    let m = model(p, width, height);
    DVector::from_iterator(
        2 * seen.len(),
        seen.iter().flat_map(|s| {
            let q = m.project(s.plate[0], s.plate[1]).unwrap_or([1e6, 1e6]);
            [q[0] - s.pixel[0], q[1] - s.pixel[1]]
        }),
    )
}

/// The starting point: the homography of the centres (no distortion)
/// decomposed with a focal length of the image's width.
fn initial(seen: &[Seen], width: u32, height: u32) -> anyhow::Result<DVector<f64>> {
    let mut a = DMatrix::<f64>::zeros(2 * seen.len(), 9);
    let (cx, cy) = ((width as f64 - 1.0) / 2.0, (height as f64 - 1.0) / 2.0);
    let f = width as f64;
    for (i, s) in seen.iter().enumerate() {
        // Normalised image coordinates: H is then [r1 r2 t] up to scale.
        let (x, y) = (s.plate[0], s.plate[1]);
        let (u, v) = ((s.pixel[0] - cx) / f, (s.pixel[1] - cy) / f);
        let rows =
            [[x, y, 1.0, 0.0, 0.0, 0.0, -u * x, -u * y, -u], [0.0, 0.0, 0.0, x, y, 1.0, -v * x, -v * y, -v]];
        for (k, row) in rows.iter().enumerate() {
            for (j, val) in row.iter().enumerate() {
                a[(2 * i + k, j)] = *val;
            }
        }
    }
    let svd = a.svd(false, true);
    let vt = svd.v_t.ok_or_else(|| anyhow::anyhow!("homography: SVD failed"))?;
    let h = vt.row(vt.nrows() - 1);
    let (h1, h2, h3) =
        (Vector3::new(h[0], h[3], h[6]), Vector3::new(h[1], h[4], h[7]), Vector3::new(h[2], h[5], h[8]));
    let mut scale = 1.0 / h1.norm();
    if h3.z * scale < 0.0 {
        scale = -scale; // the plate is in front of the camera
    }
    let (r1, r2, t) = (h1 * scale, h2 * scale, h3 * scale);
    let r = Matrix3::from_columns(&[r1, r2, r1.cross(&r2)]);
    let svd = r.svd(true, true);
    let (u, vt) = (
        svd.u.ok_or_else(|| anyhow::anyhow!("pose: SVD failed"))?,
        svd.v_t.ok_or_else(|| anyhow::anyhow!("pose: SVD failed"))?,
    );
    let r = u * vt;
    let rv = rotation_vector(&r);
    Ok(DVector::from_vec(vec![f, 0.0, 0.0, 0.0, 0.0, rv[0], rv[1], rv[2], t.x, t.y, t.z]))
}

/// Fit a camera model to the tags seen; returns it and the RMS
/// reprojection error (px).
pub fn fit(seen: &[Seen], width: u32, height: u32) -> anyhow::Result<(CameraModel, f64)> {
    if seen.len() < 12 {
        anyhow::bail!("calibrate: {} board tags found, at least 12 are needed", seen.len());
    }
    let mut p = initial(seen, width, height)?;
    let mut r = residuals(&p, seen, width, height);
    let mut cost = r.norm_squared();
    let mut lambda = 1e-3;
    for _ in 0..200 {
        let mut j = DMatrix::<f64>::zeros(r.len(), PARAMS);
        for k in 0..PARAMS {
            let h = 1e-6 * p[k].abs().max(1e-3);
            let mut q = p.clone();
            q[k] += h;
            let rp = residuals(&q, seen, width, height);
            q[k] -= 2.0 * h;
            let rm = residuals(&q, seen, width, height);
            j.set_column(k, &((rp - rm) / (2.0 * h)));
        }
        let jtj = j.transpose() * &j;
        let g = j.transpose() * &r;
        let mut improved = false;
        for _ in 0..10 {
            let mut a = jtj.clone();
            for k in 0..PARAMS {
                a[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
            }
            let Some(step) = a.lu().solve(&(-&g)) else { break };
            let q = &p + step;
            let rq = residuals(&q, seen, width, height);
            let c = rq.norm_squared();
            if c < cost {
                let done = (cost - c) < 1e-12 * cost.max(1e-300);
                (p, r, cost) = (q, rq, c);
                lambda = (lambda / 3.0).max(1e-12);
                improved = !done;
                break;
            }
            lambda *= 4.0;
        }
        if !improved {
            break;
        }
    }
    let m = model(&p, width, height);
    m.validate().map_err(anyhow::Error::msg)?;
    Ok((m, (cost / seen.len() as f64).sqrt()))
}

/// How far `estimated` maps pixels onto the plate from where `truth` has
/// them, over a 5 cm grid of the plate: RMS and max (m).
pub fn mapping_error(truth: &CameraModel, estimated: &CameraModel, half_extent: [f64; 2]) -> (f64, f64) {
    let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0);
    let steps = |h: f64| (0..=((2.0 * h / 0.05) as usize)).map(move |i| -h + 0.05 * i as f64);
    for x in steps(half_extent[0]) {
        for y in steps(half_extent[1]) {
            let Some([u, v]) = truth.project(x, y) else { continue };
            let Some([ex, ey]) = estimated.unproject(u, v) else { continue };
            let e = (ex - x).hypot(ey - y);
            sum += e * e;
            max = max.max(e);
            n += 1;
        }
    }
    ((sum / n.max(1) as f64).sqrt(), max)
}

/// Calibrate from the rig's rendered camera: render the board, detect,
/// fit, and compare with the camera's hidden truth.
pub fn from_rendered(camera: &CameraSection, half_extent: [f64; 2]) -> anyhow::Result<(Calibration, Value)> {
    let truth = camera.model().map_err(anyhow::Error::msg)?;
    let mut renderer = Renderer::board(camera).map_err(anyhow::Error::msg)?;
    let pixels = renderer.render(&ipc_types::PartStates::new()).to_vec();
    let img = image::GrayImage::from_raw(truth.width, truth.height, pixels)
        .ok_or_else(|| anyhow::anyhow!("rendered frame of the wrong size"))?;
    let seen = detect_board(img, &camera.board);
    let (estimated, rms_px) = fit(&seen, truth.width, truth.height)?;
    let (map_rms, map_max) = mapping_error(&truth, &estimated, half_extent);
    let report = json!({
        "source": "rendered",
        "tags_found": seen.len(),
        "tags_on_board": camera.board.tags(),
        "reprojection_rms_px": rms_px,
        "against_truth": {
            "plate_mapping_rms_mm": map_rms * 1e3,
            "plate_mapping_max_mm": map_max * 1e3,
            "focal_px": [truth.fx, estimated.fx],
            "k1": [truth.k1, estimated.k1],
            "k2": [truth.k2, estimated.k2],
            "p1": [truth.p1, estimated.p1],
            "p2": [truth.p2, estimated.p2],
            "translation_m": [truth.translation, estimated.translation],
        },
    });
    Ok((Calibration { plate_half_extent: half_extent, camera: estimated }, report))
}

/// Calibrate from the PNG files of `dir` (a real camera looking at the
/// board): every image's tags together.
pub fn from_images(dir: &Path, board: &Board, half_extent: [f64; 2]) -> anyhow::Result<(Calibration, Value)> {
    let files = upm_camera::files::png_files(dir)?;
    let mut seen = Vec::new();
    let mut size = None;
    for f in &files {
        let img = image::open(f).map_err(|e| anyhow::anyhow!("{}: {e}", f.display()))?.to_luma8();
        let dims = img.dimensions();
        if *size.get_or_insert(dims) != dims {
            anyhow::bail!(
                "{}: {} × {}, the first image is {} × {}",
                f.display(),
                dims.0,
                dims.1,
                size.map_or(0, |s| s.0),
                size.map_or(0, |s| s.1)
            );
        }
        seen.extend(detect_board(img, board));
    }
    let (w, h) = size.ok_or_else(|| anyhow::anyhow!("{}: no image", dir.display()))?;
    let (estimated, rms_px) = fit(&seen, w, h)?;
    let report = json!({
        "source": dir.display().to_string(),
        "images": files.len(),
        "tags_found": seen.len(),
        "reprojection_rms_px": rms_px,
    });
    Ok((Calibration { plate_half_extent: half_extent, camera: estimated }, report))
}
