//! upm-planner as a process between the PartStates and ForceRequest
//! services: the test plays vision (it publishes part states) and reads
//! the requests, so the planner is tested through its services alone.

use std::process::{Child, Command};
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use ipc_types::{ForceRequest, PartState, PartStates, service_names};

/// A service prefix no other test or rig uses.
fn unique_prefix(tag: &str) -> String {
    ipc_types::rig_node::unique_prefix(&format!("upmt_{tag}"))
}

struct Proc(Child);
impl Drop for Proc {
    fn drop(&mut self) {
        // SAFETY: plain kill(2) on our own child.
        unsafe { libc::kill(self.0.id() as libc::pid_t, libc::SIGINT) };
        let _ = self.0.wait();
    }
}

fn planner(config: &std::path::Path, extra: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_upm-planner"));
    c.arg("--config").arg(config).args(extra);
    c
}

#[test]
fn the_configured_planner_answers_part_states_with_force_requests() {
    let prefix = unique_prefix("planner");
    let dir = std::env::temp_dir().join(format!("{prefix}cfg"));
    std::fs::create_dir_all(&dir).expect("dir");
    let cfg = dir.join("rig.toml");
    // `local`: part 7 goes to (0.3, 0.2), the others hold their start.
    std::fs::write(
        &cfg,
        format!(
            "[service]\nprefix = \"{prefix}\"\n[planner]\nname = \"local\"\npart = 7\ngoal = [0.3, 0.2]\n\
             [planner.drive]\nmax_speed = 0.02\n[sim]\nseed = 3\n"
        ),
    )
    .expect("config");
    let node = NodeBuilder::new()
        .config(&ipc_types::ports::config_with_prefix(&prefix).expect("prefix"))
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .expect("node");
    let states =
        ipc_types::ports::publisher::<PartStates>(&node, service_names::PART_STATES).expect("publisher");
    let requests = ipc_types::ports::subscriber::<ForceRequest>(&node, service_names::FORCE_REQUEST)
        .expect("subscriber");
    let proc = Proc(planner(&cfg, &["--duration", "60"]).spawn().expect("planner"));
    let start = Instant::now();
    let mut got = Vec::new();
    let mut m = PartStates::new();
    m.push(PartState::new(7, 0, 0, [0.0, 0.0, 0.0], [0.0; 3])).expect("capacity");
    m.push(PartState::new(8, 1, 0, [-0.2, 0.1, 0.0], [0.0; 3])).expect("capacity");
    while got.len() < 10 && start.elapsed() < Duration::from_secs(30) {
        m.seq += 1;
        m.stamp_ns = ipc_types::monotonic_now_ns();
        states.send_copy(m).expect("send");
        while let Some(s) = requests.receive().expect("receive") {
            got.push(*s.payload());
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    drop(proc);
    drop((states, requests, node));
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(got.len() >= 10, "got {} requests", got.len());
    let last = got.last().expect("request");
    assert!(last.deadline_ns > last.stamp_ns, "a request carries its deadline");
    assert!(got.windows(2).all(|w| w[0].seq < w[1].seq));
    let force = |id| last.entries().iter().find(|e| e.part_id == id).and_then(|e| e.requested_force());
    // Part 7 is pushed towards its goal (up and to the right); part 8 is
    // at rest where it started, so it is asked for no force.
    let f7 = force(7).expect("part 7");
    assert!(f7[0] > 0.0 && f7[1] > 0.0, "{f7:?}");
    assert_eq!(force(8).expect("part 8"), [0.0, 0.0]);
}

#[test]
fn a_bad_planner_section_is_one_line_naming_the_field() {
    let dir = std::env::temp_dir().join(unique_prefix("plannercfg"));
    std::fs::create_dir_all(&dir).expect("dir");
    for (text, args, expect) in [
        ("[planner]\nname = \"walk\"\n", &[][..], "unknown variant `walk`"),
        ("[planner]\nname = \"track\"\nsorted_x = 0.5\n", &[], "unknown field `sorted_x`"),
        (
            "[planner]\nname = \"sort\"\n[planner.drive]\npart_mass = -1.0\n",
            &[],
            "planner.drive.part_mass must be positive",
        ),
        (
            "[planner]\nname = \"sort\"\n",
            &["--planner", "spin"],
            "--planner spin disagrees with planner.name = \"sort\"",
        ),
        ("", &["--planner", "gather"], "planner.name \"gather\": expected one of"),
    ] {
        let cfg = dir.join("rig.toml");
        std::fs::write(&cfg, text).expect("config");
        let out = planner(&cfg, args).args(["--duration", "1"]).output().expect("planner");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{text}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(expect), "{text}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
