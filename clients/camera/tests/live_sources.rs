//! `upm-camera --v4l2 DEVICE` and `--genicam ID`: without the device, one
//! line naming it; with Aravis's fake GenICam camera (builds with the
//! `genicam` feature), frames of the calibrated size reach a stranger's
//! subscriber, numbered and stamped in order.

use std::process::Command;

use upm_test_harness::TestRig;

fn camera(rig: &TestRig, source: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_upm-camera"));
    c.arg("--config").arg(&rig.config).args(source).args(["--duration", "5"]);
    c
}

fn config(prefix: &str) -> String {
    format!("[service]\nprefix = \"{prefix}\"\n\n[camera]\nwidth = 320\nheight = 240\nframe_hz = 20.0\n")
}

/// Exit status 1 and exactly one line on stderr, containing `needle`.
fn fails_in_one_line(mut c: Command, needle: &str) {
    let out = c.output().expect("upm-camera runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.contains(needle), "names {needle}: {err}");
}

#[test]
fn a_missing_or_wrong_device_is_one_line_naming_it() {
    let rig = TestRig::new("live", config);
    fails_in_one_line(camera(&rig, &["--v4l2", "/dev/upm-no-such-camera"]), "/dev/upm-no-such-camera");
    // A device node that is no camera.
    fails_in_one_line(camera(&rig, &["--v4l2", "/dev/null"]), "/dev/null");
    fails_in_one_line(camera(&rig, &["--genicam", "UPM-no-such-camera"]), "UPM-no-such-camera");
}

#[cfg(feature = "genicam")]
#[test]
fn the_fake_genicam_camera_publishes_frames_of_the_calibrated_size() {
    use std::time::{Duration, Instant};
    use upm_test_harness::Running;

    let rig = TestRig::new("genicam", config);
    let frames = ipc_types::ports::frame_subscriber(rig.node()).expect("subscriber");
    let running = Running(camera(&rig, &["--genicam", "Fake_1"]).spawn().expect("upm-camera"));
    let mut got = Vec::new();
    let start = Instant::now();
    while got.len() < 10 && start.elapsed() < Duration::from_secs(10) {
        while let Some(f) = frames.receive().expect("receive") {
            let h = *f.user_header();
            assert_eq!(h.check(f.payload().len(), 320, 240), Ok(()));
            // Aravis's fake camera draws a moving pattern, not a flat frame.
            let (lo, hi) = f.payload().iter().fold((255u8, 0u8), |(lo, hi), &p| (lo.min(p), hi.max(p)));
            assert!(hi > lo, "a flat frame");
            got.push((h.seq, h.stamp_ns));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    drop(running);
    assert!(got.len() >= 10, "{} frames in 10 s", got.len());
    assert!(got.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 > w[0].1), "{got:?}");
}
