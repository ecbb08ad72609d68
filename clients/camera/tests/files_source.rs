//! `upm-camera --files DIR`: PNG files replayed as frames, as a stranger's
//! subscriber sees them; files that do not decode or have another size are
//! counted and skipped.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use upm_test_harness::{Running, TestRig};

#[test]
fn png_files_are_published_in_order_and_bad_ones_skipped() {
    let rig = TestRig::new("files", |prefix| format!("[service]\nprefix = \"{prefix}\"\n"));
    let dir = rig.config.with_file_name("frames");
    std::fs::create_dir_all(&dir).expect("dir");
    let (w, h) = (64u32, 48u32);
    for i in 0..3u32 {
        let img = image::GrayImage::from_fn(w, h, |x, y| image::Luma([((x + y + 10 * i) % 256) as u8]));
        img.save(dir.join(format!("frame_{i:03}.png"))).expect("png");
    }
    // A colour frame is taken as mono8; a broken one and one of another
    // size are skipped.
    image::RgbImage::from_pixel(w, h, image::Rgb([200, 200, 200]))
        .save(dir.join("frame_003.png"))
        .expect("png");
    std::fs::write(dir.join("frame_004.png"), b"not a png").expect("write");
    image::GrayImage::new(32, 32).save(dir.join("frame_005.png")).expect("png");
    let frames = ipc_types::ports::frame_subscriber(rig.node()).expect("subscriber");
    let camera = |extra: &[&str]| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_upm-camera"));
        c.arg("--config").arg(&rig.config).arg("--files").arg(&dir).args(["--rate", "10"]).args(extra);
        c
    };
    // Looping, read while it runs (a finished publisher takes its frames
    // with it): files 0, 1, 2, the colour one, then file 0 again.
    let looping = Running(camera(&["--loop", "--duration", "20"]).spawn().expect("upm-camera"));
    let mut got = Vec::new();
    let start = Instant::now();
    while got.len() < 5 && start.elapsed() < Duration::from_secs(20) {
        while let Some(f) = frames.receive().expect("receive") {
            let hdr = *f.user_header();
            assert_eq!(hdr.check(f.payload().len(), w, h), Ok(()));
            got.push((hdr.seq, f.payload().to_vec()));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    drop(looping);
    assert_eq!(got.iter().take(5).map(|g| g.0).collect::<Vec<_>>(), vec![1, 2, 3, 4, 5]);
    // Once through: the summary counts what was skipped.
    let out = camera(&["--duration", "10"]).stderr(Stdio::piped()).output().expect("upm-camera");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("4 frames published, 1 files unreadable, 1 of another size"), "{err}");
    let expected =
        |i: u32| (0..h).flat_map(|y| (0..w).map(move |x| ((x + y + 10 * i) % 256) as u8)).collect::<Vec<_>>();
    for (i, frame) in got.iter().take(3).enumerate() {
        assert_eq!(frame.1, expected(i as u32), "frame {i}");
    }
    assert!(got[3].1.iter().all(|&p| p == 200), "colour → mono8");
    assert_eq!(got[4].1, expected(0), "looped");
}
