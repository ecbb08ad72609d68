//! `upm bench vision`: the camera path's accuracy against the rendered
//! camera's hidden truth, and vision's per-frame time beside OpenCV's
//! threshold + connected components + moments on the same frames, in the
//! same run.
//!
//! Per case (resolution, part count, outlines): seeded parts of two
//! classes (discs of 15 mm radius; or 24 mm squares and 30 mm triangles,
//! turning at up to 2 rad/s), apart at the start, moving up to 5 cm/s and
//! passing through each other (no physics here; position, angle and class
//! errors and misses count separated parts, those within 3 mm of touching
//! are counted apart), rendered frame by frame at 30 Hz through
//! the default `[camera]` lens scaled to the sensor; vision (background
//! model, threshold, labelling, moments, detection through the calibration
//! `upm calibrate camera` finds from the rendered board, tracker) times
//! every frame. OpenCV runs from Python
//! (`opencv-python-headless` in a venv under the target directory, made on
//! first use, one thread) on the very same frames: a global threshold at
//! 0.7 × the plate's median, masked to vision's region of interest,
//! `connectedComponentsWithStats` (8-connected) and `cv2.moments` of each
//! part-sized component. OpenCV's global threshold does less than vision's
//! background model, which follows uneven light. Without Python or the
//! package the reference is skipped and says so.

use core::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use ipc_types::{PartState, PartStates};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};
use upm_camera::{CameraSection, ClassLook, Renderer};
use upm_vision::VisionSection;
use upm_vision::class_outline::ClassOutline;
use upm_vision::part_look::PartLook;
use upm_vision::pipeline::FramePipeline;

/// One bench case: a sensor, how many parts, and whether they are
/// polygons (class 0 squares, class 1 triangles) or discs.
#[derive(Debug, Clone, Copy)]
struct Case {
    width: u32,
    height: u32,
    parts: usize,
    polygons: bool,
}

impl Case {
    /// The two classes' outlines as the camera renders them.
    fn classes(self) -> [ClassLook; 2] {
        let [dark, grey] = [0.1, 0.4];
        // Radii in mm, then m: the same numbers as when the type held mm.
        if self.polygons {
            [
                ClassLook {
                    level: dark,
                    radius: 24.0 * core::f64::consts::FRAC_1_SQRT_2 * 1e-3,
                    shape: ClassOutline::Square,
                },
                ClassLook { level: grey, radius: 30.0 / 3f64.sqrt() * 1e-3, shape: ClassOutline::Triangle },
            ]
        } else {
            [dark, grey].map(|level| ClassLook { level, radius: 0.015, shape: ClassOutline::Disc })
        }
    }
}

fn sorted(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v
}

/// The default camera, its focal length scaled so the plate and its
/// markers (≈ 2.3 × 1.3 m) fill the sensor.
fn camera_for(case: Case) -> CameraSection {
    let base = CameraSection::default();
    let h = base.mount[2];
    let focal = (case.width as f64 / 2.3).min(case.height as f64 / 1.3) * h;
    CameraSection {
        width: case.width,
        height: case.height,
        focal_px: focal,
        classes: case.classes().to_vec(),
        ..base
    }
}

/// Seeded separated parts, half of each class: (class, pose, velocity).
/// Polygons also turn.
fn parts(n: usize, seed: u64, turning: bool) -> Vec<(u32, [f64; 3], [f64; 3])> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out: Vec<(u32, [f64; 3], [f64; 3])> = Vec::new();
    while out.len() < n {
        let p = [rng.random_range(-0.85..0.85), rng.random_range(-0.38..0.38)];
        let (theta, omega) =
            if turning { (rng.random_range(-PI..PI), rng.random_range(-2.0..2.0)) } else { (0.0, 0.0) };
        if out.iter().all(|(_, q, _)| (q[0] - p[0]).hypot(q[1] - p[1]) > 0.1) {
            let v = [rng.random_range(-0.05..0.05), rng.random_range(-0.05..0.05), omega];
            out.push(((out.len() % 2) as u32, [p[0], p[1], theta], v));
        }
    }
    out
}

fn one_case(case: Case, frames: usize, rounds: usize, dir: &Path) -> anyhow::Result<(Value, PathBuf)> {
    let cam = camera_for(case);
    // Vision works through what calibration found, as in a real rig.
    let (cal, cal_report) = upm_commands::calibrate_camera::from_rendered(&cam, cam.half_extent)?;
    let model = cal.camera;
    let vision_section = VisionSection { classes: cam.vision_classes(), ..VisionSection::default() };
    let mut vision = FramePipeline::new(&cal, &vision_section);
    let mut renderer = Renderer::new(&cam).map_err(anyhow::Error::msg)?;
    let mut truth_parts = parts(case.parts, 1000 + case.parts as u64, case.polygons);
    let dt = 1.0 / 30.0;
    let raw = dir.join(format!("frames_{}x{}_{}_{}.raw", case.width, case.height, case.parts, case.polygons));
    let mut raw_bytes = Vec::with_capacity(frames * (case.width * case.height) as usize);
    let (mut times, mut err_mm, mut err_px) = (Vec::new(), Vec::new(), Vec::new());
    let (mut missed, mut false_found, mut class_errors) = (0u64, 0u64, 0u64);
    let (mut near_err_mm, mut near_missed) = (Vec::new(), 0u64);
    let mut angle_err_deg = [Vec::new(), Vec::new()];
    for _ in 0..frames {
        let mut truth = PartStates::new();
        for (i, (class, p, v)) in truth_parts.iter().enumerate() {
            let _ = truth.push(PartState::new(i as u32, *class, 0, *p, *v));
        }
        let pixels = renderer.render(&truth);
        raw_bytes.extend_from_slice(pixels);
        let start = Instant::now();
        if vision.process(pixels, case.width, case.height, case.width as usize, dt).is_err() {
            vision.no_frame(dt);
        }
        times.push(start.elapsed().as_secs_f64() * 1e6);
        let found = vision.detections();
        // Match each part to the nearest detection within 10 mm. The
        // parts here pass through each other (no physics): accuracy
        // targets are for separated parts, a part within 3 mm of touching
        // another is counted apart.
        let mut used = vec![false; found.len()];
        let radius = vision_section.classes.iter().map(|l| l.radius).fold(0.0, f64::max);
        for (k, (class, p, _)) in truth_parts.iter().enumerate() {
            let separated = truth_parts
                .iter()
                .enumerate()
                .all(|(j, (_, q, _))| j == k || (q[0] - p[0]).hypot(q[1] - p[1]) > 2.0 * radius + 0.003);
            let near = found
                .iter()
                .enumerate()
                .filter(|(i, d)| !used[*i] && (d.x - p[0]).hypot(d.y - p[1]) < 0.01)
                .min_by(|a, b| {
                    (a.1.x - p[0]).hypot(a.1.y - p[1]).total_cmp(&(b.1.x - p[0]).hypot(b.1.y - p[1]))
                });
            match near {
                Some((i, d)) => {
                    used[i] = true;
                    let e = (d.x - p[0]).hypot(d.y - p[1]);
                    if separated {
                        err_mm.push(e * 1e3);
                        err_px.push(e / model.metres_per_pixel(p[0], p[1]).unwrap_or(f64::NAN));
                        class_errors += u64::from(d.class != *class);
                        let shape = vision_section.classes[*class as usize].shape;
                        if shape.corners() > 0 {
                            angle_err_deg[*class as usize]
                                .push(shape.wrap(d.theta - p[2]).abs().to_degrees());
                        }
                    } else {
                        near_err_mm.push(e * 1e3);
                    }
                }
                None if separated => missed += 1,
                None => near_missed += 1,
            }
        }
        false_found += used.iter().filter(|u| !**u).count() as u64;
        // Move on, bouncing off the plate's working area.
        for (_, p, v) in truth_parts.iter_mut() {
            p[2] += v[2] * dt;
            for k in 0..2 {
                p[k] += v[k] * dt;
                let lim = if k == 0 { 0.9 } else { 0.42 };
                if p[k].abs() > lim {
                    v[k] = -v[k];
                }
            }
        }
    }
    std::fs::write(&raw, &raw_bytes)?;
    // The same frames again, through a real vision process.
    let frame_list: Vec<&[u8]> = raw_bytes.chunks_exact((case.width * case.height) as usize).collect();
    let latency =
        crate::bench_vision_latency::measure(&cal, &vision_section, &frame_list, rounds, 30.0, dir)?;
    // The reference gets vision's region of interest as a mask.
    let mut mask = vec![0u8; (case.width * case.height) as usize];
    for (v, &(a, b)) in vision.roi_spans().iter().enumerate() {
        let row = v * case.width as usize;
        mask[row + a as usize..row + b as usize].fill(255);
    }
    std::fs::write(raw.with_extension("mask"), &mask)?;
    let (times, err_mm, err_px, near_err_mm) =
        (sorted(times), sorted(err_mm), sorted(err_px), sorted(near_err_mm));
    let [square_deg, triangle_deg] = angle_err_deg.map(sorted);
    let angle_p99 =
        |v: &[f64]| if v.is_empty() { Value::Null } else { json!(upm_stats::percentile_or_nan(v, 0.99)) };
    let part_area_mm2 = vision_section.classes.iter().map(PartLook::area).fold(0.0, f64::max) * 1e6;
    let mpp = model.metres_per_pixel(0.0, 0.0).unwrap_or(f64::NAN);
    Ok((
        json!({
            "width": case.width,
            "height": case.height,
            "parts": case.parts,
            "outlines": if case.polygons { "squares+triangles" } else { "discs" },
            "part_area_mm2": part_area_mm2,
            "frames": frames,
            "mm_per_px": mpp * 1e3,
            "upm_p50_us": upm_stats::percentile_or_nan(&times, 0.5),
            "upm_p99_us": upm_stats::percentile_or_nan(&times, 0.99),
            "position_err_p50_mm": upm_stats::percentile_or_nan(&err_mm, 0.5),
            "position_err_p99_mm": upm_stats::percentile_or_nan(&err_mm, 0.99),
            "position_err_p99_px": upm_stats::percentile_or_nan(&err_px, 0.99),
            "square_angle_err_p99_deg": angle_p99(&square_deg),
            "triangle_angle_err_p99_deg": angle_p99(&triangle_deg),
            "class_errors": class_errors,
            "missed": missed,
            "false_detections": false_found,
            "touching_sightings": near_err_mm.len() as u64 + near_missed,
            "touching_missed": near_missed,
            "touching_err_p50_mm": upm_stats::percentile_or_nan(&near_err_mm, 0.5),
            "split_detections": vision.counts.split,
            "merged_blobs": vision.counts.merged,
            "cut_blobs": vision.counts.cut,
            "latency_p50_us": latency.p50_us,
            "latency_p99_us": latency.p99_us,
            "latency_max_us": latency.max_us,
            "latency_source_publish_p50_us": latency.publish_p50_us,
            "latency_frames": latency.sent,
            "latency_answered": latency.answered,
            "latency_pm_qos": latency.pm_qos,
            "calibration_mapping_rms_mm": cal_report["against_truth"]["plate_mapping_rms_mm"],
        }),
        raw,
    ))
}

/// A Python with numpy and OpenCV: the system's, else a venv under the
/// target directory made on first use. `Err` says why there is none.
fn opencv_python(dir: &Path) -> Result<PathBuf, String> {
    let works = |py: &Path| {
        Command::new(py).args(["-c", "import cv2, numpy"]).output().is_ok_and(|o| o.status.success())
    };
    let system = PathBuf::from("python3");
    if works(&system) {
        return Ok(system);
    }
    let venv = dir.join("opencv-venv");
    let py = venv.join("bin/python3");
    if !works(&py) {
        eprintln!("upm bench vision: installing opencv-python-headless into {}", venv.display());
        let made = Command::new("python3").args(["-m", "venv", "--clear"]).arg(&venv).status();
        if !made.is_ok_and(|s| s.success()) {
            return Err("python3 -m venv failed (is python3 installed?)".into());
        }
        let pip = Command::new(&py)
            .args(["-m", "pip", "install", "-q", "opencv-python-headless", "numpy"])
            .status()
            .map_err(|e| format!("pip: {e}"))?;
        if !pip.success() || !works(&py) {
            return Err("pip could not install opencv-python-headless".into());
        }
    }
    Ok(py)
}

const OPENCV_SCRIPT: &str = r#"
import sys, time, numpy as np, cv2
path, w, h, n, amin, amax = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6])
cv2.setNumThreads(1)
frames = np.fromfile(path, dtype=np.uint8).reshape(n, h, w)
mask = np.fromfile(path[:-3] + "mask", dtype=np.uint8).reshape(h, w)
times = []
for f in frames:
    t = float(np.median(f[mask > 0])) * 0.7
    start = time.perf_counter()
    _, bw = cv2.threshold(f, t, 255, cv2.THRESH_BINARY_INV)
    bw = cv2.bitwise_and(bw, mask)
    count, labels, stats, centroids = cv2.connectedComponentsWithStats(bw, connectivity=8)
    area = stats[:, cv2.CC_STAT_AREA]
    for i in np.nonzero((area >= amin) & (area <= amax))[0]:
        x, y, ww, hh = stats[i, :4]
        cv2.moments((labels[y:y + hh, x:x + ww] == i).astype(np.uint8), binaryImage=True)
    times.append((time.perf_counter() - start) * 1e6)
times.sort()
print(times[len(times) // 2])
"#;

/// OpenCV's p50 µs on the frames in `raw`.
fn opencv_p50(py: &Path, raw: &Path, v: &Value) -> Result<f64, String> {
    let mpp = v["mm_per_px"].as_f64().unwrap_or(1.0) * 1e-3;
    let area = v["part_area_mm2"].as_f64().unwrap_or(f64::NAN) * 1e-6 / (mpp * mpp);
    let out = Command::new(py)
        .args(["-c", OPENCV_SCRIPT])
        .arg(raw)
        .args([&v["width"], &v["height"], &v["frames"]].map(|x| x.to_string()))
        .args([(0.5 * area).to_string(), (1.5 * area).to_string()])
        .output()
        .map_err(|e| format!("python: {e}"))?;
    if !out.status.success() {
        return Err(format!("opencv script: {}", String::from_utf8_lossy(&out.stderr).trim()));
    }
    String::from_utf8_lossy(&out.stdout).trim().parse().map_err(|e| format!("opencv script output: {e}"))
}

/// Every case, then the OpenCV reference on the same frames.
pub fn run(quick: bool) -> anyhow::Result<Value> {
    let (frames, rounds) = if quick { (8, 2) } else { (60, 3) };
    let case = |width, height, parts, polygons| Case { width, height, parts, polygons };
    let cases = [
        case(1280, 1024, 10, false),
        case(2240, 1216, 10, true),
        case(2240, 1216, 10, false),
        case(2240, 1216, 32, false),
        case(2048, 2048, 10, false),
        case(2048, 2048, 32, false),
        case(2048, 2048, 32, true),
    ];
    let target = std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| PathBuf::from("target"), PathBuf::from);
    let dir = target.join("bench-vision");
    std::fs::create_dir_all(&dir)?;
    let mut rows = Vec::new();
    let mut raws = Vec::new();
    for case in if quick { &cases[..2] } else { &cases[..] } {
        let (v, raw) = one_case(*case, frames, rounds, &dir)?;
        rows.push(v);
        raws.push(raw);
    }
    let reference = match opencv_python(&dir) {
        Ok(py) => {
            for (row, raw) in rows.iter_mut().zip(&raws) {
                let p50 = opencv_p50(&py, raw, row);
                row["opencv_p50_us"] = p50.as_ref().map_or(Value::Null, |p| json!(p));
                row["ratio_p50"] =
                    p50.map_or(Value::Null, |p| json!(row["upm_p50_us"].as_f64().unwrap_or(f64::NAN) / p));
            }
            Value::String("opencv-python-headless, same frames, same process run".into())
        }
        Err(why) => {
            eprintln!("upm bench vision: OpenCV reference skipped: {why}");
            Value::String(format!("skipped: {why}"))
        }
    };
    for raw in &raws {
        let _ = std::fs::remove_file(raw);
        let _ = std::fs::remove_file(raw.with_extension("mask"));
    }
    Ok(json!({ "host": crate::host_facts::read_all(), "reference": reference, "cases": rows }))
}

pub fn to_text(v: &Value) -> String {
    let mut s = format!(
        "{}\nreference: {}\n{:>11} {:>5} {:>6} {:>9} {:>9} {:>9} {:>7} {:>9} {:>9} {:>7} {:>7} {:>6} {:>6} {:>6} {:>8}",
        crate::host_facts::to_text(&v["host"]),
        v["reference"].as_str().unwrap_or("?"),
        "sensor",
        "parts",
        "mm/px",
        "upm p50",
        "upm p99",
        "cv p50",
        "ratio",
        "err p50",
        "err p99",
        "sq° p99",
        "tri° p99",
        "class",
        "missed",
        "false",
        "age p99"
    );
    for c in v["cases"].as_array().into_iter().flatten() {
        let f = |k: &str| c[k].as_f64().unwrap_or(f64::NAN);
        s += &format!(
            "\n{:>11} {:>5} {:>6.2} {:>9.0} {:>9.0} {:>9.0} {:>7.2} {:>9.3} {:>9.3} {:>7.3} {:>7.3} {:>6} {:>6} {:>6} {:>8.0}",
            format!("{}x{}", c["width"], c["height"]),
            c["parts"],
            f("mm_per_px"),
            f("upm_p50_us"),
            f("upm_p99_us"),
            f("opencv_p50_us"),
            f("ratio_p50"),
            f("position_err_p50_mm"),
            f("position_err_p99_mm"),
            f("square_angle_err_p99_deg"),
            f("triangle_angle_err_p99_deg"),
            c["class_errors"],
            c["missed"],
            c["false_detections"],
            f("latency_p99_us")
        );
    }
    s + "\n(µs per frame; position errors in mm and angle errors in degrees against the renderer's truth; age: frame stamp → PartStates at the core's side through a upm vision process, µs)"
}
