//! The camera client: tracker unit behaviour, and upm-vision as a process
//! between upm-core's simulator ground truth and the PartStates service.

mod common;

use std::process::{Child, Command};
use std::time::{Duration, Instant};

use ipc_types::{PartStates, service_names};
use upm_clients::vision::{Detection, Tracker, TrackerParams};

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
fn vision_process_publishes_tracked_part_states_from_the_simulator() {
    let prefix = common::unique_prefix("vision");
    let dir = std::env::temp_dir().join(format!("{prefix}cfg"));
    std::fs::create_dir_all(&dir).expect("dir");
    let cfg = dir.join("core.toml");
    std::fs::write(
        &cfg,
        format!(
            "[service]\nprefix = \"{prefix}\"\n[vision]\nframe_hz = 50.0\nlatency_ms = 5.0\n\
             [[sim.parts]]\nid = 1\nclass = 0\nshape = \"disc\"\nsize = 0.02\nmass = 0.01\nposition = [0.5, 0.0]\n\
             [[sim.parts]]\nid = 2\nclass = 1\nshape = \"point\"\nsize = 0.005\nmass = 0.01\nposition = [-0.75, 0.25]\n"
        ),
    )
    .expect("config");
    let core = Proc(
        Command::new(env!("CARGO_BIN_EXE_upm-core"))
            .arg("--config")
            .arg(&cfg)
            .args(["--truth-hz", "1000", "--duration", "60"])
            .spawn()
            .expect("core"),
    );
    let vision = Proc(
        Command::new(env!("CARGO_BIN_EXE_upm-vision"))
            .arg("--config")
            .arg(&cfg)
            .args(["--duration", "60"])
            .spawn()
            .expect("vision"),
    );
    let node = common::plain_node(&prefix);
    let sub = common::subscriber::<PartStates>(&node, service_names::PART_STATES);
    let start = Instant::now();
    let mut frames = Vec::new();
    while frames.len() < 20 && start.elapsed() < Duration::from_secs(30) {
        while let Some(s) = sub.receive().expect("receive") {
            frames.push(*s.payload());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    drop(vision);
    drop(core);
    common::remove_prefix(&prefix);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(frames.len() >= 20, "got {} frames", frames.len());
    let last = frames.last().expect("frame");
    assert_eq!(last.len(), 2);
    for (id, class, pos) in [(1, 0, [0.5, 0.0]), (2, 1, [-0.75, 0.25])] {
        let p = last.parts().iter().find(|p| p.id == id).expect("id tracked");
        assert_eq!(p.class, class);
        // Resting parts on an idle plate: within a few noise sigmas.
        assert!((p.x - pos[0]).hypot(p.y - pos[1]) < 0.003, "{p:?}");
    }
    // Frames are ordered and stamped.
    assert!(frames.windows(2).all(|w| w[0].seq < w[1].seq && w[0].stamp_ns < w[1].stamp_ns));
}
