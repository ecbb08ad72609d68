//! `upm calibrate camera` as a user runs it: from the rendered board it
//! recovers the rendered camera's hidden mapping of the plate, and bad
//! input (too few tags, images that show no board, a missing directory)
//! is one line naming what is wrong.

use std::process::Command;

use upm_camera::{Board, CameraSection};
use upm_commands::calibrate_camera::{from_rendered, mapping_error};
use upm_vision::calibration::Calibration;

fn upm(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_upm")).args(args).output().expect("upm runs")
}

#[test]
fn the_rendered_board_gives_back_the_hidden_camera() {
    let dir = std::env::temp_dir().join(format!("upm_calibrate_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let out = dir.join("cal.toml");
    let o = upm(&["calibrate", "camera", "--json", "--out", out.to_str().expect("path")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let cal = Calibration::load(&out).expect("a calibration vision loads");
    let _ = std::fs::remove_dir_all(&dir);
    let found = report["tags_found"].as_u64().unwrap_or(0);
    assert!(found as f64 >= 0.95 * Board::default().tags() as f64, "{report}");
    assert!(report["reprojection_rms_px"].as_f64().unwrap_or(9.0) < 0.2, "{report}");
    // The file holds the fitted model, not the camera's true one.
    let truth = CameraSection::default().model().expect("model");
    assert_ne!(cal.camera, truth);
    let (rms, max) = mapping_error(&truth, &cal.camera, [1.0, 0.5]);
    assert!(rms < 0.3e-3 && max < 0.6e-3, "plate mapping rms {} mm, max {} mm", rms * 1e3, max * 1e3);
}

#[test]
fn a_board_too_small_to_fit_is_refused() {
    let cam =
        CameraSection { board: Board { cols: 3, rows: 3, ..Board::default() }, ..CameraSection::default() };
    let e = from_rendered(&cam, [1.0, 0.5]).expect_err("9 tags");
    assert!(e.to_string().contains("at least 12 are needed"), "{e}");
}

#[test]
fn images_without_a_board_or_no_images_are_one_line() {
    let dir = std::env::temp_dir().join(format!("upm_calibrate_blank_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    image::GrayImage::from_pixel(320, 240, image::Luma([128])).save(dir.join("blank.png")).expect("png");
    let o = upm(&["calibrate", "camera", "--images", dir.to_str().expect("path"), "--out", "/dev/null"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("0 board tags found"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    let missing = dir.join("nothing-here");
    let o = upm(&["calibrate", "camera", "--images", missing.to_str().expect("path")]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("nothing-here"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
