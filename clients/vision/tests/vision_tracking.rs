//! The camera client: tracker unit behaviour, and upm-vision as a process
//! between the ground-truth service and the PartStates service. The test
//! plays the core's part (it publishes the ground truth), so vision is
//! tested through its services alone.

use std::process::{Child, Command};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use ipc_types::{PartState, PartStates, service_names};
use upm_vision::{Detection, Tracker, TrackerParams};

/// A service prefix no other test or rig uses.
fn unique_prefix(tag: &str) -> String {
    ipc_types::rig_node::unique_prefix(&format!("upmt_{tag}"))
}

#[test]
fn tracker_keeps_ids_through_reordering_and_estimates_velocity() {
    let mut t = Tracker::new(TrackerParams::default());
    let dt = 1.0 / 30.0;
    let v = [0.05, -0.02];
    for frame in 0..60 {
        let time = frame as f64 * dt;
        let a = Detection { x: 0.1 + v[0] * time, y: 0.2 + v[1] * time, theta: 0.0, class: 0 };
        let b = Detection { x: -0.3, y: 0.1, theta: 0.0, class: 1 };
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
    let d = Detection { x: 0.0, y: 0.0, theta: 0.0, class: 0 };
    t.update(&[d], 0.0);
    for _ in 0..3 {
        t.update(&[], 0.03);
    }
    assert!(t.tracks().is_empty());
    t.update(&[d], 0.03);
    assert_eq!(t.tracks()[0].id, 2);
}

struct Proc(Child);
impl Drop for Proc {
    fn drop(&mut self) {
        // SAFETY: plain kill(2) on our own child.
        unsafe { libc::kill(self.0.id() as libc::pid_t, libc::SIGINT) };
        let _ = self.0.wait();
    }
}

#[test]
fn vision_process_publishes_tracked_part_states_from_the_ground_truth() {
    let prefix = unique_prefix("vision");
    let dir = std::env::temp_dir().join(format!("{prefix}cfg"));
    std::fs::create_dir_all(&dir).expect("dir");
    let cfg = dir.join("rig.toml");
    // Sections vision does not read (here [sim]) are left to other processes.
    std::fs::write(
        &cfg,
        format!(
            "[service]\nprefix = \"{prefix}\"\n[vision]\nframe_hz = 50.0\nlatency_ms = 5.0\n[sim]\nseed = 3\n"
        ),
    )
    .expect("config");
    let node = NodeBuilder::new()
        .config(&ipc_types::ports::config_with_prefix(&prefix).expect("prefix"))
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .expect("node");
    let truth =
        ipc_types::ports::publisher::<PartStates>(&node, service_names::SIM_GROUND_TRUTH).expect("publisher");
    let sub =
        ipc_types::ports::subscriber::<PartStates>(&node, service_names::PART_STATES).expect("subscriber");
    let vision = Proc(
        Command::new(env!("CARGO_BIN_EXE_upm-vision"))
            .arg("--config")
            .arg(&cfg)
            .args(["--duration", "60"])
            .spawn()
            .expect("vision"),
    );
    let truth_parts = [(1, 0, [0.5, 0.0]), (2, 1, [-0.75, 0.25])];
    let start = Instant::now();
    let mut frames = Vec::new();
    while frames.len() < 20 && start.elapsed() < Duration::from_secs(30) {
        let mut m = PartStates::new();
        m.stamp_ns = ipc_types::monotonic_now_ns();
        for (id, class, [x, y]) in truth_parts {
            m.push(PartState::new(id, class, 0, [x, y, 0.0], [0.0; 3])).expect("capacity");
        }
        truth.send_copy(m).expect("truth");
        while let Some(s) = sub.receive().expect("receive") {
            frames.push(*s.payload());
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    drop(vision);
    drop((truth, sub, node));
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    let _ = std::fs::remove_dir_all(&dir);
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
    let dir = std::env::temp_dir().join(unique_prefix("visioncfg"));
    std::fs::create_dir_all(&dir).expect("dir");
    for (text, expect) in [
        ("[vision]\nframe_hz = \"fast\"\n", "vision.frame_hz: invalid type"),
        ("[vision]\nframe_hz = 0.0\n", "vision.frame_hz must be in (0, 1000]"),
        ("[vision]\nnoise = 1.0\n", "unknown field `noise`"),
        ("[service]\nprefix = \"a b\"\n", "service.prefix \"a b\" must be"),
    ] {
        let cfg = dir.join("rig.toml");
        std::fs::write(&cfg, text).expect("config");
        let out = Command::new(env!("CARGO_BIN_EXE_upm-vision"))
            .arg("--config")
            .arg(&cfg)
            .args(["--duration", "1"])
            .output()
            .expect("vision");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{text}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(expect), "{text}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
