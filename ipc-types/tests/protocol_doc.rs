//! docs/protocol.md against the code: every payload table (type name, size,
//! alignment, each field's offset, size and type), the services and their
//! payloads, the service and inbox settings, the protocol version, the
//! reject codes and FeedStatus's capacities. Edit the doc with the code,
//! or this fails.

mod wire_layout;

use iceoryx2::prelude::ZeroCopySend;
use ipc_types::wake_event::WakeEvent;
use ipc_types::{
    CoreCommand, ExplicitSchedule, FeedStatus, ForceRequest, FrameHeader, LineStatus, PROTOCOL_VERSION,
    PartStates, PickCommand, RecipeCommand, RejectReason, RejectedKind, Rejection, RigInfo, Schedule,
    Telemetry, service_names,
};

fn doc() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/protocol.md"))
        .expect("docs/protocol.md")
}

/// The cells of a table row (`| a | b |` → ["a", "b"]), backticks removed.
fn cells(line: &str) -> Vec<String> {
    line.trim().trim_matches('|').split('|').map(|c| c.trim().trim_matches('`').to_owned()).collect()
}

/// Rows of the first table after the line that starts with `heading`.
fn table_after(doc: &str, heading: &str) -> Vec<Vec<String>> {
    table_with_header(doc, heading).into_iter().skip(2).collect() // header and |---|
}

/// The same table with its header row (and the |---| row).
fn table_with_header(doc: &str, heading: &str) -> Vec<Vec<String>> {
    let start = doc.find(heading).unwrap_or_else(|| panic!("docs/protocol.md lacks {heading:?}"));
    doc[start..]
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .map(cells)
        .collect()
}

fn type_name<T: ZeroCopySend>() -> &'static str {
    // SAFETY: only reads the name the derive generated.
    unsafe { <T as ZeroCopySend>::type_name() }
}

#[test]
fn every_payload_table_matches_the_rust_layout() {
    let doc = doc();
    let layouts = wire_layout::all();
    let sections = doc.lines().filter(|l| l.starts_with("### `upm::")).count();
    assert_eq!(sections, layouts.len(), "one section per payload type");
    for l in &layouts {
        let heading = format!("### `{}` ({}, {} bytes, align {})", l.type_name, l.rust, l.size, l.align);
        let rows = table_after(&doc, &heading);
        let documented: Vec<(String, String, String, String)> =
            rows.iter().map(|r| (r[0].clone(), r[1].clone(), r[2].clone(), r[3].clone())).collect();
        let actual: Vec<(String, String, String, String)> = l
            .fields
            .iter()
            .map(|f| (f.name.to_owned(), f.offset.to_string(), f.size.to_string(), f.ty.clone()))
            .collect();
        assert_eq!(documented, actual, "{}: (field, offset, size, type) in docs/protocol.md", l.rust);
    }
}

#[test]
fn services_settings_version_and_reject_codes_match() {
    let doc = doc();
    assert!(doc.contains(&format!("`PROTOCOL_VERSION` = {PROTOCOL_VERSION}")), "protocol version");
    let services: Vec<(String, String)> =
        table_after(&doc, "| service |").into_iter().map(|r| (r[0].clone(), r[1].clone())).collect();
    let expected: Vec<(String, String)> = [
        (service_names::PART_STATES, type_name::<PartStates>()),
        (service_names::FORCE_REQUEST, type_name::<ForceRequest>()),
        (service_names::EXPLICIT_SCHEDULE, type_name::<ExplicitSchedule>()),
        (service_names::CORE_COMMAND, type_name::<CoreCommand>()),
        (service_names::SCHEDULE, type_name::<Schedule>()),
        (service_names::TELEMETRY, type_name::<Telemetry>()),
        (service_names::REJECTION, type_name::<Rejection>()),
        (service_names::RIG_INFO, type_name::<RigInfo>()),
        (service_names::SIM_GROUND_TRUTH, type_name::<PartStates>()),
        (service_names::FEED, type_name::<FeedStatus>()),
        (service_names::PICK, type_name::<PickCommand>()),
        (service_names::RECIPE, type_name::<RecipeCommand>()),
        (service_names::RECIPE_ACTIVE, type_name::<RecipeCommand>()),
        (service_names::LINE, type_name::<LineStatus>()),
    ]
    .iter()
    .map(|(s, t)| (s.to_string(), t.to_string()))
    .collect();
    assert_eq!(services, expected, "the services table");
    let frames: Vec<(String, String)> =
        table_after(&doc, "| frame service |").into_iter().map(|r| (r[0].clone(), r[1].clone())).collect();
    let expected_frames =
        vec![(service_names::CAMERA_FRAME.to_owned(), type_name::<FrameHeader>().to_owned())];
    assert_eq!(frames, expected_frames, "the frame services table");
    assert_eq!(services.len() + frames.len(), service_names::ALL.len(), "every service is documented");
    use ipc_types::ports::{FRAME_BUFFER, FRAME_SUBSCRIBERS};
    let frame_settings: Vec<(String, String)> =
        table_after(&doc, "| frame setting |").iter().map(|r| (r[0].clone(), r[1].clone())).collect();
    let expected_frame_settings: Vec<(String, String)> = [
        ("max_publishers", ipc_types::ports::MAX_PUBLISHERS.to_string()),
        ("max_subscribers", FRAME_SUBSCRIBERS.to_string()),
        ("subscriber_max_buffer_size", FRAME_BUFFER.to_string()),
        ("history_size", "0".to_owned()),
        ("enable_safe_overflow", "true".to_owned()),
        ("max_nodes", ipc_types::ports::MAX_NODES.to_string()),
    ]
    .iter()
    .map(|(k, v)| (k.to_string(), v.clone()))
    .collect();
    assert_eq!(frame_settings, expected_frame_settings, "the frame service settings table");

    use ipc_types::ports::{HISTORY, MAX_NODES, MAX_PUBLISHERS, MAX_SUBSCRIBERS, SUBSCRIBER_BUFFER};
    // What UPM leaves to iceoryx2: the defaults of its built-in config.
    let defaults = iceoryx2::config::Config::default().defaults;
    let settings = table_after(&doc, "| setting |");
    let expected = [
        ("max_publishers", MAX_PUBLISHERS.to_string()),
        ("max_subscribers", MAX_SUBSCRIBERS.to_string()),
        ("subscriber_max_buffer_size", SUBSCRIBER_BUFFER.to_string()),
        ("history_size", HISTORY.to_string()),
        ("enable_safe_overflow", "true".to_owned()),
        ("max_nodes", MAX_NODES.to_string()),
        (
            "subscriber_max_borrowed_samples",
            defaults.publish_subscribe.subscriber_max_borrowed_samples.to_string(),
        ),
    ];
    let documented: Vec<(String, String)> = settings.iter().map(|r| (r[0].clone(), r[1].clone())).collect();
    let expected: Vec<(String, String)> = expected.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
    assert_eq!(documented, expected, "the service settings table");
    let events = [WakeEvent::Inbox, WakeEvent::Frame, WakeEvent::PartStates];
    for e in events {
        assert!(doc.contains(&format!("event service `{}`", e.service())), "the {e:?} event");
    }
    // One column per event; every setting, UPM's and iceoryx2's defaults.
    let table = table_with_header(&doc, "| event setting |");
    let header: Vec<String> = table[0][1..].to_vec();
    let want_header: Vec<String> = events.iter().map(|e| e.service().to_owned()).collect();
    assert_eq!(header, want_header, "the event settings table's columns");
    let ev = &defaults.event;
    let none_or = |v: Option<usize>| v.map_or_else(|| "none".to_owned(), |v| v.to_string());
    let deadline = ev.deadline.map_or_else(|| "none".to_owned(), |d| format!("{d:?}"));
    let rows: Vec<(&str, Vec<String>)> = vec![
        ("max_notifiers", events.iter().map(|_| MAX_SUBSCRIBERS.to_string()).collect()),
        ("max_listeners", events.iter().map(|e| e.max_listeners().to_string()).collect()),
        ("max_nodes", events.iter().map(|_| MAX_NODES.to_string()).collect()),
        ("event_id_max_value", events.iter().map(|_| ev.event_id_max_value.to_string()).collect()),
        ("notifier_created_event", events.iter().map(|_| none_or(ev.notifier_created_event)).collect()),
        ("notifier_dropped_event", events.iter().map(|_| none_or(ev.notifier_dropped_event)).collect()),
        ("notifier_dead_event", events.iter().map(|_| none_or(ev.notifier_dead_event)).collect()),
        ("deadline", events.iter().map(|_| deadline.clone()).collect()),
    ];
    for (name, want) in rows {
        let row = table.iter().find(|r| r[0] == name).unwrap_or_else(|| panic!("no {name} row"));
        assert_eq!(row[1..].to_vec(), want, "the event settings table, {name}");
    }

    // Each kind by the Rust name of the message it refuses (`pick` is a
    // `PickCommand`, `recipe` a `RecipeCommand`: the kind is named after
    // the service).
    let kinds: Vec<String> = RejectedKind::ALL
        .iter()
        .map(|k| {
            let name = match k {
                RejectedKind::PartStates => type_name::<PartStates>(),
                RejectedKind::ForceRequest => type_name::<ForceRequest>(),
                RejectedKind::ExplicitSchedule => type_name::<ExplicitSchedule>(),
                RejectedKind::CoreCommand => type_name::<CoreCommand>(),
                RejectedKind::PickCommand => type_name::<PickCommand>(),
                RejectedKind::RecipeCommand => type_name::<RecipeCommand>(),
            };
            let rust = name.trim_start_matches("upm::").split('.').next().unwrap_or(name);
            format!("{} `{rust}`", k.code())
        })
        .collect();
    assert!(doc.contains(&kinds.join(", ")), "Rejection.kind codes: {}", kinds.join(", "));

    let codes: Vec<(String, String)> =
        table_after(&doc, "| code | reason |").iter().map(|r| (r[0].clone(), r[1].clone())).collect();
    let expected: Vec<(String, String)> =
        RejectReason::ALL.iter().map(|r| (r.index().to_string(), r.as_str().to_owned())).collect();
    assert_eq!(codes, expected, "the reject codes table");
}

/// FeedStatus's capacities, as its table and section name them.
#[test]
fn feed_status_capacities_match() {
    let doc = doc();
    for (name, value) in
        [("MAX_PICK_POSES", ipc_types::MAX_PICK_POSES), ("FEED_RECENT_PICKS", ipc_types::FEED_RECENT_PICKS)]
    {
        let named = format!("0 … {value} (`{name}`");
        assert!(doc.contains(&named), "docs/protocol.md lacks {named:?}");
    }
}

/// RecipeCommand's path capacity, as its table and section name it.
#[test]
fn recipe_path_capacity_matches() {
    let doc = doc();
    let named = format!("0 … {} (`RECIPE_PATH_BYTES`", ipc_types::RECIPE_PATH_BYTES);
    assert!(doc.contains(&named), "docs/protocol.md lacks {named:?}");
}

/// Prints the layout tables docs/protocol.md starts from (a helper, not a
/// check): `cargo test -p ipc-types --test protocol_doc -- --ignored --nocapture`.
#[test]
#[ignore]
fn print_layout_tables() {
    for l in wire_layout::all() {
        println!("### `{}` ({}, {} bytes, align {})\n", l.type_name, l.rust, l.size, l.align);
        println!("| field | offset | size | type | meaning |\n|---|---|---|---|---|");
        for f in &l.fields {
            println!("| `{}` | {} | {} | `{}` |  |", f.name, f.offset, f.size, f.ty);
        }
        println!();
    }
}
