//! The Python bindings (`clients/python/upm_ipc/messages.py`) against the
//! Rust types: every mirrored struct's size, type name and field offsets
//! and sizes, and the shared constants. Needs `python3` (ctypes only, no
//! iceoryx2).

mod wire_layout;

use std::collections::BTreeMap;
use std::process::Command;

use ipc_types::{
    MAX_CURLS, MAX_PARTS, MAX_SHAPE_VERTICES, MAX_SLOTS, PROTOCOL_VERSION, SHAPE_DISC, SHAPE_POINT,
    SHAPE_POLYGON, service_names,
};

/// What the Python module says: `name value` lines (see the script below).
fn python_layout() -> BTreeMap<String, String> {
    let messages = concat!(env!("CARGO_MANIFEST_DIR"), "/../clients/python/upm_ipc/messages.py");
    let script = r#"
import ctypes, importlib.util, sys
spec = importlib.util.spec_from_file_location("messages", sys.argv[1])
m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)
for s in (m.PartState, m.PartStates, m.ForceEntry, m.ForceRequest, m.ScheduleSlot, m.Schedule, m.Rejection, m.FrameHeader, m.RigCenter, m.RigInfo, m.PickPoseState, m.PickEvent, m.FeedStatus, m.PickCommand, m.RecipeCommand, m.LineStatus):
    print(f"{s.__name__}.size {ctypes.sizeof(s)}")
    print(f"{s.__name__}.align {ctypes.alignment(s)}")
    print(f"{s.__name__}.type_name {s.type_name()}")
    for f in s._fields_:
        d = getattr(s, f[0])
        print(f"{s.__name__}.{f[0].rstrip('_')} {d.offset}+{d.size}")
for c in ("PROTOCOL_VERSION", "MAX_PARTS", "MAX_CURLS", "MAX_SLOTS", "MAX_CENTERS", "MAX_SHAPE_VERTICES", "SHAPE_POINT", "SHAPE_DISC", "SHAPE_POLYGON", "PART_STATES", "FORCE_REQUEST", "SCHEDULE", "TELEMETRY", "REJECTION", "RIG_INFO", "FEED", "PICK", "RECIPE", "RECIPE_ACTIVE", "LINE", "CAMERA_FRAME", "INBOX_EVENT", "FRAME_EVENT", "PART_STATES_EVENT",
          "MAX_PUBLISHERS", "MAX_SUBSCRIBERS", "SUBSCRIBER_BUFFER", "HISTORY", "MAX_NODES", "INBOX_MAX_LISTENERS", "PART_STATES_MAX_LISTENERS", "FRAME_SUBSCRIBERS", "FRAME_BUFFER", "RIG_PREFIX_BYTES", "MAX_PICK_POSES", "FEED_RECENT_PICKS", "RECIPE_PATH_BYTES"):
    print(f"{c} {getattr(m, c)}")
print("REJECTED_KINDS " + ",".join(m.REJECTED_KINDS))
print("REJECT_REASONS " + ",".join(m.REJECT_REASONS))
"#;
    let out = Command::new("python3").args(["-c", script, messages]).output().expect("python3 runs");
    assert!(out.status.success(), "python3: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_once(' ').map(|(k, v)| (k.to_owned(), v.to_owned())))
        .collect()
}

#[test]
fn python_messages_match_the_rust_types_field_by_field() {
    let mirrored = [
        "PartState",
        "PartStates",
        "ForceEntry",
        "ForceRequest",
        "ScheduleSlot",
        "Schedule",
        "Rejection",
        "FrameHeader",
        "RigCenter",
        "RigInfo",
        "PickPoseState",
        "PickEvent",
        "FeedStatus",
        "PickCommand",
        "RecipeCommand",
        "LineStatus",
    ];
    let mut rust = BTreeMap::new();
    for l in wire_layout::all().into_iter().filter(|l| mirrored.contains(&l.rust)) {
        rust.insert(format!("{}.size", l.rust), l.size.to_string());
        rust.insert(format!("{}.align", l.rust), l.align.to_string());
        rust.insert(format!("{}.type_name", l.rust), l.type_name.to_owned());
        for f in &l.fields {
            // Padding can hide a wrong type from the offsets alone.
            rust.insert(format!("{}.{}", l.rust, f.name), format!("{}+{}", f.offset, f.size));
        }
    }
    for (name, value) in [
        ("PROTOCOL_VERSION", PROTOCOL_VERSION.to_string()),
        ("MAX_PARTS", MAX_PARTS.to_string()),
        ("MAX_CURLS", MAX_CURLS.to_string()),
        ("MAX_SLOTS", MAX_SLOTS.to_string()),
        ("MAX_CENTERS", ipc_types::MAX_CENTERS.to_string()),
        ("RIG_PREFIX_BYTES", ipc_types::RIG_PREFIX_BYTES.to_string()),
        ("RIG_INFO", service_names::RIG_INFO.to_owned()),
        ("FEED", service_names::FEED.to_owned()),
        ("PICK", service_names::PICK.to_owned()),
        ("RECIPE", service_names::RECIPE.to_owned()),
        ("RECIPE_ACTIVE", service_names::RECIPE_ACTIVE.to_owned()),
        ("LINE", service_names::LINE.to_owned()),
        ("RECIPE_PATH_BYTES", ipc_types::RECIPE_PATH_BYTES.to_string()),
        ("MAX_PICK_POSES", ipc_types::MAX_PICK_POSES.to_string()),
        ("FEED_RECENT_PICKS", ipc_types::FEED_RECENT_PICKS.to_string()),
        ("PART_STATES_EVENT", ipc_types::wake_event::WakeEvent::PartStates.service().to_owned()),
        ("PART_STATES_MAX_LISTENERS", ipc_types::wake_event::PART_STATES_LISTENERS.to_string()),
        ("MAX_SHAPE_VERTICES", MAX_SHAPE_VERTICES.to_string()),
        ("SHAPE_POINT", SHAPE_POINT.to_string()),
        ("SHAPE_DISC", SHAPE_DISC.to_string()),
        ("SHAPE_POLYGON", SHAPE_POLYGON.to_string()),
        ("PART_STATES", service_names::PART_STATES.to_owned()),
        ("FORCE_REQUEST", service_names::FORCE_REQUEST.to_owned()),
        ("SCHEDULE", service_names::SCHEDULE.to_owned()),
        ("TELEMETRY", service_names::TELEMETRY.to_owned()),
        ("REJECTION", service_names::REJECTION.to_owned()),
        ("CAMERA_FRAME", service_names::CAMERA_FRAME.to_owned()),
        ("FRAME_EVENT", ipc_types::wake_event::WakeEvent::Frame.service().to_owned()),
        ("INBOX_EVENT", service_names::INBOX_EVENT.to_owned()),
        ("FRAME_SUBSCRIBERS", ipc_types::ports::FRAME_SUBSCRIBERS.to_string()),
        ("FRAME_BUFFER", ipc_types::ports::FRAME_BUFFER.to_string()),
        ("MAX_PUBLISHERS", ipc_types::ports::MAX_PUBLISHERS.to_string()),
        ("MAX_SUBSCRIBERS", ipc_types::ports::MAX_SUBSCRIBERS.to_string()),
        ("SUBSCRIBER_BUFFER", ipc_types::ports::SUBSCRIBER_BUFFER.to_string()),
        ("HISTORY", ipc_types::ports::HISTORY.to_string()),
        ("MAX_NODES", ipc_types::ports::MAX_NODES.to_string()),
        ("INBOX_MAX_LISTENERS", ipc_types::wake_event::MAX_LISTENERS.to_string()),
        (
            "REJECTED_KINDS",
            ipc_types::RejectedKind::ALL.iter().map(|k| k.as_str()).collect::<Vec<_>>().join(","),
        ),
        (
            "REJECT_REASONS",
            ipc_types::RejectReason::ALL.iter().map(|r| r.as_str()).collect::<Vec<_>>().join(","),
        ),
    ] {
        rust.insert(name.to_owned(), value);
    }
    let python = python_layout();
    // Every Rust entry is in Python with the same value, and Python has no
    // field Rust lacks (a renamed or extra field is a drift too).
    for (k, v) in &rust {
        assert_eq!(python.get(k), Some(v), "{k}: Rust {v}, Python {:?}", python.get(k));
    }
    let extra: Vec<_> = python.keys().filter(|k| !rust.contains_key(*k)).collect();
    assert!(extra.is_empty(), "Python has what Rust does not: {extra:?}");
}
