//! upm-planner as a process between the PartStates and ForceRequest
//! services: the test plays vision (it publishes part states) and reads
//! the requests, so the planner is tested through its services alone.

use std::process::Command;
use std::time::Duration;

use ipc_types::{ForceRequest, PartState, PartStates, service_names};
use upm_test_harness::{Running, TestRig};

fn planner(config: &std::path::Path, extra: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_upm-planner"));
    c.arg("--config").arg(config).args(extra);
    c
}

#[test]
fn the_configured_planner_answers_part_states_with_force_requests() {
    // `local`: part 7 goes to (0.3, 0.2), the others hold their start.
    let rig = TestRig::new("planner", |prefix| {
        format!(
            "[service]\nprefix = \"{prefix}\"\n[planner]\nname = \"local\"\npart = 7\ngoal = [0.3, 0.2]\n\
             [planner.drive]\nmax_speed = 0.02\n[sim]\nseed = 3\n"
        )
    });
    let states =
        ipc_types::ports::publisher::<PartStates>(rig.node(), service_names::PART_STATES).expect("publisher");
    let requests = ipc_types::ports::subscriber::<ForceRequest>(rig.node(), service_names::FORCE_REQUEST)
        .expect("subscriber");
    let _planner = Running(planner(&rig.config, &["--duration", "60"]).spawn().expect("planner"));
    let mut m = PartStates::new();
    m.push(PartState::new(7, 0, 0, [0.0, 0.0, 0.0], [0.0; 3])).expect("capacity");
    m.push(PartState::new(8, 1, 0, [-0.2, 0.1, 0.0], [0.0; 3])).expect("capacity");
    let got = TestRig::exchange(&requests, 10, Duration::from_secs(30), Duration::from_millis(5), || {
        m.seq += 1;
        m.stamp_ns = ipc_types::monotonic_now_ns();
        states.send_copy(m).expect("send");
    });
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
    let rig = TestRig::new("plannercfg", |_| String::new());
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
        std::fs::write(&rig.config, text).expect("config");
        let out = planner(&rig.config, args).args(["--duration", "1"]).output().expect("planner");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{text}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(expect), "{text}: {err}");
    }
}
