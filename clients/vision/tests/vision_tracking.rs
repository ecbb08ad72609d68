//! The camera client: tracker unit behaviour, and upm-vision as a process
//! between the ground-truth service and the PartStates service. The test
//! plays the core's part (it publishes the ground truth), so vision is
//! tested through its services alone.

use std::process::Command;
use std::time::Duration;

use ipc_types::{PartState, PartStates, service_names};
use upm_test_harness::{Running, TestRig};
use upm_vision::{Detection, Tracker, TrackerParams};

#[test]
fn tracker_keeps_ids_through_reordering_and_estimates_velocity() {
    let mut t = Tracker::new(TrackerParams::default());
    let dt = 1.0 / 30.0;
    let v = [0.05, -0.02];
    for frame in 0..60 {
        let time = frame as f64 * dt;
        let a = Detection { x: 0.1 + v[0] * time, y: 0.2 + v[1] * time, theta: 0.0, class: 0, period: 0.0 };
        let b = Detection { x: -0.3, y: 0.1, theta: 0.0, class: 1, period: 0.0 };
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
    let params = TrackerParams { max_missed: 2, ..TrackerParams::default() };
    let mut t = Tracker::new(params);
    let d = Detection { x: 0.0, y: 0.0, theta: 0.0, class: 0, period: 0.0 };
    t.update(&[d], 0.0);
    for _ in 0..3 {
        t.update(&[], 0.03);
    }
    assert!(t.tracks().is_empty());
    t.update(&[d], 0.03);
    assert_eq!(t.tracks()[0].id, 2);
}

#[test]
fn vision_process_publishes_tracked_part_states_from_the_ground_truth() {
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
    let _vision = Running(
        Command::new(env!("CARGO_BIN_EXE_upm-vision"))
            .arg("--config")
            .arg(&rig.config)
            .args(["--duration", "60"])
            .spawn()
            .expect("vision"),
    );
    let truth_parts = [(1, 0, [0.5, 0.0]), (2, 1, [-0.75, 0.25])];
    let frames = TestRig::exchange(&sub, 20, Duration::from_secs(30), Duration::from_millis(1), || {
        let mut m = PartStates::new();
        m.stamp_ns = ipc_types::monotonic_now_ns();
        for (id, class, [x, y]) in truth_parts {
            m.push(PartState::new(id, class, 0, [x, y, 0.0], [0.0; 3])).expect("capacity");
        }
        truth.send_copy(m).expect("truth");
    });
    assert!(frames.len() >= 20, "got {} frames", frames.len());
    let last = frames.last().expect("frame");
    assert_eq!(last.len(), 2);
    for (_, class, pos) in truth_parts {
        // The tracker numbers parts itself; find each by where it is.
        let p = last.parts().iter().find(|p| p.class == class).expect("class tracked");
        // Resting parts: within a few noise sigmas.
        assert!((p.x - pos[0]).hypot(p.y - pos[1]) < 0.003, "{p:?}");
    }
    // Frames are ordered and stamped.
    assert!(frames.windows(2).all(|w| w[0].seq < w[1].seq && w[0].stamp_ns < w[1].stamp_ns));
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
