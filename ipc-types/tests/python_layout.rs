//! The Python bindings (`clients/python/upm_ipc/messages.py`) against the
//! Rust types: every mirrored struct's size, type name and field offsets,
//! and the shared constants. Needs `python3` (ctypes only, no iceoryx2).

use core::mem::{offset_of, size_of};
use std::collections::BTreeMap;
use std::process::Command;

use iceoryx2::prelude::ZeroCopySend;
use ipc_types::{
    ForceEntry, ForceRequest, MAX_CURLS, MAX_PARTS, MAX_SLOTS, PROTOCOL_VERSION, PartState, PartStates,
    Schedule, ScheduleSlot, service_names,
};

fn type_name<T: ZeroCopySend>() -> &'static str {
    // SAFETY: only reads the name the derive generated.
    unsafe { <T as ZeroCopySend>::type_name() }
}

/// What Python says: `name value` lines (see the script below).
fn python_layout() -> BTreeMap<String, String> {
    let messages = concat!(env!("CARGO_MANIFEST_DIR"), "/../clients/python/upm_ipc/messages.py");
    let script = r#"
import ctypes, importlib.util, sys
spec = importlib.util.spec_from_file_location("messages", sys.argv[1])
m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)
for s in (m.PartState, m.PartStates, m.ForceEntry, m.ForceRequest, m.ScheduleSlot, m.Schedule):
    print(f"{s.__name__}.size {ctypes.sizeof(s)}")
    print(f"{s.__name__}.type_name {s.type_name()}")
    for f in s._fields_:
        d = getattr(s, f[0])
        print(f"{s.__name__}.{f[0].rstrip('_')} {d.offset}+{d.size}")
for c in ("PROTOCOL_VERSION", "MAX_PARTS", "MAX_CURLS", "MAX_SLOTS", "PART_STATES", "FORCE_REQUEST", "SCHEDULE", "TELEMETRY", "INBOX_EVENT",
          "MAX_PUBLISHERS", "MAX_SUBSCRIBERS", "SUBSCRIBER_BUFFER", "HISTORY", "MAX_NODES", "INBOX_MAX_LISTENERS"):
    print(f"{c} {getattr(m, c)}")
"#;
    let out = Command::new("python3").args(["-c", script, messages]).output().expect("python3 runs");
    assert!(out.status.success(), "python3: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_once(' ').map(|(k, v)| (k.to_owned(), v.to_owned())))
        .collect()
}

/// `Type.field offset+size` for every field (padding can hide a wrong
/// type from the offsets alone), the type's size and its type name.
macro_rules! layout {
    ($into:ident, $t:ident { $($field:ident),* $(,)? }) => {
        $into.insert(format!("{}.size", stringify!($t)), size_of::<$t>().to_string());
        $into.insert(format!("{}.type_name", stringify!($t)), type_name::<$t>().to_owned());
        // SAFETY: every payload is integers and floats, for which zero is valid.
        let zero: $t = unsafe { core::mem::zeroed() };
        $(
            $into.insert(
                format!("{}.{}", stringify!($t), stringify!($field)),
                format!("{}+{}", offset_of!($t, $field), core::mem::size_of_val(&zero.$field)),
            );
        )*
    };
}

#[test]
fn python_messages_match_the_rust_types_field_by_field() {
    let mut rust = BTreeMap::new();
    layout!(rust, PartState { id, class, friction_class, reserved, x, y, theta, vx, vy, omega });
    layout!(rust, PartStates { protocol_version, count, seq, stamp_ns, parts });
    layout!(rust, ForceEntry { part_id, force_flag, curl_flag, reserved, fx, fy, curl });
    layout!(rust, ForceRequest { protocol_version, count, seq, stamp_ns, deadline_ns, entries });
    layout!(rust, ScheduleSlot { center_index, reserved, x, y, k });
    layout!(
        rust,
        Schedule {
            protocol_version,
            count,
            seq,
            stamp_ns,
            cycle,
            solve_time_ns,
            residual,
            condition,
            rank,
            saturated,
            slots
        }
    );
    for (name, value) in [
        ("PROTOCOL_VERSION", PROTOCOL_VERSION.to_string()),
        ("MAX_PARTS", MAX_PARTS.to_string()),
        ("MAX_CURLS", MAX_CURLS.to_string()),
        ("MAX_SLOTS", MAX_SLOTS.to_string()),
        ("PART_STATES", service_names::PART_STATES.to_owned()),
        ("FORCE_REQUEST", service_names::FORCE_REQUEST.to_owned()),
        ("SCHEDULE", service_names::SCHEDULE.to_owned()),
        ("TELEMETRY", service_names::TELEMETRY.to_owned()),
        ("INBOX_EVENT", service_names::INBOX_EVENT.to_owned()),
        ("MAX_PUBLISHERS", ipc_types::ports::MAX_PUBLISHERS.to_string()),
        ("MAX_SUBSCRIBERS", ipc_types::ports::MAX_SUBSCRIBERS.to_string()),
        ("SUBSCRIBER_BUFFER", ipc_types::ports::SUBSCRIBER_BUFFER.to_string()),
        ("HISTORY", ipc_types::ports::HISTORY.to_string()),
        ("MAX_NODES", ipc_types::ports::MAX_NODES.to_string()),
        ("INBOX_MAX_LISTENERS", ipc_types::inbox_event::MAX_LISTENERS.to_string()),
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
