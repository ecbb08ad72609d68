//! The camera client: tracker unit behaviour, and upm-vision as a process
//! between the ground-truth service and the PartStates service. The test
//! plays the core's part (it publishes the ground truth), so vision is
//! tested through its services alone.

use std::process::Command;
use std::time::Duration;

use ipc_types::{PartState, PartStates, SHAPE_DISC, SHAPE_POINT, SHAPE_POLYGON, service_names};
use upm_test_harness::{Running, TestRig};
use upm_vision::class_outline::ClassOutline;
use upm_vision::{BodyOutline, Camera, Detection, Tracker, VisionSection, part_states};

/// A point detection (no outline) at rest.
fn at(x: f64, y: f64, class: u32) -> Detection {
    Detection { x, y, theta: 0.0, class, period: 0.0, outline: BodyOutline::POINT }
}

/// A part of each outline: a point, a disc and a (not regular) polygon.
fn outlined_truth() -> [PartState; 3] {
    let point = PartState::new(1, 0, 0, [0.5, 0.0, 0.0], [0.0; 3]);
    let disc = PartState::new(2, 1, 0, [-0.5, 0.2, 0.3], [0.0; 3]).with_disc(0.021);
    let quad = [[0.03, -0.01], [0.02, 0.02], [-0.02, 0.015], [-0.01, -0.02]];
    let polygon = PartState::new(3, 2, 0, [0.0, -0.3, -1.0], [0.0; 3]).with_polygon(&quad).expect("4 fit");
    [point, disc, polygon]
}

#[test]
fn tracker_keeps_ids_through_reordering_and_estimates_velocity() {
    let mut t = Tracker::new(&VisionSection::default());
    let dt = 1.0 / 30.0;
    let v = [0.05, -0.02];
    for frame in 0..60 {
        let time = frame as f64 * dt;
        let a = at(0.1 + v[0] * time, 0.2 + v[1] * time, 0);
        let b = at(-0.3, 0.1, 1);
        // The camera reports parts in any order.
        let dets = if frame % 2 == 0 { vec![a, b] } else { vec![b, a] };
        t.update(&dets, if frame == 0 { 0.0 } else { dt });
    }
    let tracks = t.tracks();
    assert_eq!(tracks.len(), 2);
    let a = tracks.iter().find(|t| t.id == 1).expect("track 1");
    assert_eq!(a.class, 0);
    assert!((a.velocity[0] - v[0]).abs() < 2e-3 && (a.velocity[1] - v[1]).abs() < 2e-3, "{a:?}");
    let b = tracks.iter().find(|t| t.id == 2).expect("track 2");
    assert!(b.velocity[0].abs() < 1e-9);
}

#[test]
fn tracker_drops_lost_tracks_and_starts_new_ones() {
    let params = VisionSection { max_missed_frames: 2, ..VisionSection::default() };
    let mut t = Tracker::new(&params);
    let d = at(0.0, 0.0, 0);
    t.update(&[d], 0.0);
    for _ in 0..3 {
        t.update(&[], 0.03);
    }
    assert!(t.tracks().is_empty());
    t.update(&[d], 0.03);
    assert_eq!(t.tracks()[0].id, 2);
}

#[test]
fn a_track_publishes_the_outline_of_its_latest_detection() {
    let mut t = Tracker::new(&VisionSection::default());
    let square = ClassOutline::Square.body_outline(0.02);
    let disc = ClassOutline::Disc.body_outline(0.015);
    let d = Detection { outline: square, ..at(0.1, 0.1, 0) };
    t.update(&[d, Detection { outline: disc, ..at(-0.2, 0.1, 1) }], 0.0);
    assert_eq!(t.tracks().iter().map(|t| t.outline).collect::<Vec<_>>(), [square, disc]);
    // The same track, now seen with another outline: the newest wins.
    let bigger = ClassOutline::Square.body_outline(0.025);
    t.update(&[Detection { outline: bigger, ..d }], 0.03);
    assert_eq!((t.tracks()[0].id, t.tracks()[0].outline), (1, bigger));
    assert_eq!(t.tracks()[1].outline, disc, "an unseen track keeps its outline");
    let mut out = PartStates::new();
    part_states(t.tracks(), 1, 5, &mut out);
    assert_eq!(out.parts().len(), 1, "only tracks seen this frame");
    let p = out.parts()[0];
    assert_eq!((p.shape, p.vertex_count), (SHAPE_POLYGON, 4));
    assert!(p.polygon().iter().all(|v| (v[0].hypot(v[1]) - 0.025).abs() < 1e-12), "{p:?}");
    assert_eq!(p.check_shape(1.0), Ok(()));
    t.update(&[Detection { outline: bigger, ..d }, Detection { outline: disc, ..at(-0.2, 0.1, 1) }], 0.03);
    part_states(t.tracks(), 2, 6, &mut out);
    assert_eq!((out.parts()[1].shape, out.parts()[1].radius), (SHAPE_DISC, 0.015));
}

#[test]
fn the_simulated_camera_and_tracker_pass_truth_outlines_through() {
    let params = VisionSection { noise_m: 0.001, noise_rad: 0.01, ..VisionSection::default() };
    let mut cam = Camera::new(&params).expect("camera");
    let mut tracker = Tracker::new(&VisionSection::default());
    let parts = outlined_truth();
    let mut out = PartStates::new();
    for frame in 0..3u64 {
        let mut truth = PartStates::new();
        truth.stamp_ns = 1_000_000_000 + frame * 33_000_000;
        for p in parts {
            truth.push(p).expect("capacity");
        }
        cam.capture(&truth);
        let seen = cam.ready(truth.stamp_ns).expect("no latency");
        for (d, p) in seen.detections.iter().zip(&parts) {
            assert_eq!(d.outline, BodyOutline::of(p));
            assert!(d.x != p.x, "the pose is seen with noise");
        }
        tracker.update(&seen.detections, if frame == 0 { 0.0 } else { 0.033 });
        part_states(tracker.tracks(), frame + 1, truth.stamp_ns, &mut out);
    }
    assert_eq!(out.parts().len(), parts.len());
    for p in parts {
        let q = out.parts().iter().find(|q| q.class == p.class).expect("tracked");
        assert_eq!(BodyOutline::of(q), BodyOutline::of(&p), "class {}", p.class);
    }
    assert_eq!(out.parts()[0].shape, SHAPE_POINT);
}

#[test]
fn vision_process_publishes_tracked_part_states_from_the_ground_truth_and_wakes_planners() {
    // Sections vision does not read (here [sim]) are left to other processes.
    let rig = TestRig::new("vision", |prefix| {
        format!(
            "[service]\nprefix = \"{prefix}\"\n[vision]\nframe_hz = 50.0\nlatency_ms = 5.0\n[sim]\nseed = 3\n"
        )
    });
    let truth = ipc_types::ports::publisher::<PartStates>(rig.node(), service_names::SIM_GROUND_TRUTH)
        .expect("publisher");
    let sub = ipc_types::ports::subscriber::<PartStates>(rig.node(), service_names::PART_STATES)
        .expect("subscriber");
    // A planner's wake-up: vision notifies it after each PartStates.
    let woken =
        ipc_types::wake_event::wake_listener(rig.node(), ipc_types::wake_event::WakeEvent::PartStates)
            .expect("listener");
    let _vision = Running(
        Command::new(env!("CARGO_BIN_EXE_upm-vision"))
            .arg("--config")
            .arg(&rig.config)
            .args(["--duration", "60"])
            .spawn()
            .expect("vision"),
    );
    let truth_parts = outlined_truth();
    let frames = TestRig::exchange(&sub, 20, Duration::from_secs(30), Duration::from_millis(1), || {
        let mut m = PartStates::new();
        m.stamp_ns = ipc_types::monotonic_now_ns();
        for p in truth_parts {
            m.push(p).expect("capacity");
        }
        truth.send_copy(m).expect("truth");
    });
    assert!(frames.len() >= 20, "got {} frames", frames.len());
    let last = frames.last().expect("frame");
    assert_eq!(last.len(), truth_parts.len());
    for t in truth_parts {
        // The tracker numbers parts itself; find each by its class.
        let p = last.parts().iter().find(|p| p.class == t.class).expect("class tracked");
        // Resting parts: within a few noise sigmas.
        assert!((p.x - t.x).hypot(p.y - t.y) < 0.003, "{p:?}");
        // The outline as the simulator gave it.
        assert_eq!(BodyOutline::of(p), BodyOutline::of(&t), "{p:?}");
    }
    // Frames are ordered and stamped.
    assert!(frames.windows(2).all(|w| w[0].seq < w[1].seq && w[0].stamp_ns < w[1].stamp_ns));
    let mut wake_ups = 0;
    woken.try_wait(|_| wake_ups += 1).expect("the listener works");
    assert!(wake_ups > 0, "vision never notified the part states event");
}

#[test]
fn a_bad_vision_section_is_one_line_naming_the_field() {
    let rig = TestRig::new("visioncfg", |_| String::new());
    for (text, expect) in [
        ("[vision]\nframe_hz = \"fast\"\n", "vision.frame_hz: invalid type"),
        ("[vision]\nframe_hz = 0.0\n", "vision.frame_hz must be in (0, 1000]"),
        ("[vision]\nnoise = 1.0\n", "unknown field `noise`"),
        ("[service]\nprefix = \"a b\"\n", "service.prefix \"a b\" must be"),
    ] {
        std::fs::write(&rig.config, text).expect("config");
        let out = Command::new(env!("CARGO_BIN_EXE_upm-vision"))
            .arg("--config")
            .arg(&rig.config)
            .args(["--duration", "1"])
            .output()
            .expect("vision");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{text}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(expect), "{text}: {err}");
    }
}
