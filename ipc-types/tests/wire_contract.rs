//! The cross-process contract: type names carry the protocol version and
//! service names are valid iceoryx2 names.

use core::mem::{align_of, offset_of, size_of};

use iceoryx2::prelude::{ServiceName, ZeroCopySend};
use ipc_types::{
    CoreCommand, ExplicitSchedule, ForceRequest, MAX_PARTS, MAX_SHAPE_VERTICES, PROTOCOL_VERSION, PartState,
    PartStates, SHAPE_DISC, SHAPE_POINT, SHAPE_POLYGON, Schedule, ShapeError, Telemetry, service_names,
};

fn type_name<T: ZeroCopySend>() -> &'static str {
    // SAFETY: only reads the name the derive generated.
    unsafe { <T as ZeroCopySend>::type_name() }
}

#[test]
fn payload_type_names_carry_the_protocol_version() {
    let suffix = format!(".v{PROTOCOL_VERSION}");
    let names = [
        type_name::<PartStates>(),
        type_name::<ForceRequest>(),
        type_name::<ExplicitSchedule>(),
        type_name::<Schedule>(),
        type_name::<Telemetry>(),
        type_name::<CoreCommand>(),
        type_name::<PartState>(),
        type_name::<ipc_types::RigInfo>(),
        type_name::<ipc_types::RigCenter>(),
        type_name::<ipc_types::Rejection>(),
        type_name::<ipc_types::FrameHeader>(),
        type_name::<ipc_types::FeedStatus>(),
        type_name::<ipc_types::PickEvent>(),
        type_name::<ipc_types::PickPoseState>(),
        type_name::<ipc_types::PickCommand>(),
        type_name::<ipc_types::RecipeCommand>(),
        type_name::<ipc_types::LineStatus>(),
    ];
    for name in names {
        assert!(name.starts_with("upm::") && name.ends_with(&suffix), "{name} lacks upm::…{suffix}");
    }
    let mut unique = names.to_vec();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), names.len(), "type names must differ: {names:?}");
}

#[test]
fn service_names_are_valid_and_distinct() {
    for name in service_names::ALL {
        assert!(ServiceName::new(name).is_ok(), "{name} is not a valid iceoryx2 service name");
        assert!(name.starts_with("upm/"), "{name}");
    }
    let mut unique = service_names::ALL.to_vec();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), service_names::ALL.len());
}

#[test]
fn monotonic_clock_moves_forward() {
    let a = ipc_types::monotonic_now_ns();
    std::thread::sleep(std::time::Duration::from_millis(2));
    let b = ipc_types::monotonic_now_ns();
    assert!(a > 0 && b >= a + 1_000_000, "a={a} b={b}");
}

/// A part's outline: `shape` after the class codes, the rest after `omega`.
#[test]
fn part_state_carries_its_outline_where_the_contract_says() {
    assert_eq!(PROTOCOL_VERSION, 6);
    assert_eq!((SHAPE_POINT, SHAPE_DISC, SHAPE_POLYGON, MAX_SHAPE_VERTICES), (0, 1, 2, 8));
    assert_eq!((size_of::<PartState>(), align_of::<PartState>()), (208, 8));
    assert_eq!(size_of::<PartStates>(), 24 + MAX_PARTS * 208);
    let offsets = [
        offset_of!(PartState, shape),
        offset_of!(PartState, omega),
        offset_of!(PartState, radius),
        offset_of!(PartState, vertex_count),
        offset_of!(PartState, reserved),
        offset_of!(PartState, vertices),
    ];
    assert_eq!(offsets, [12, 56, 64, 72, 76, 80]);
}

/// v6: `Schedule.at_bound` (and `reserved`) after `saturated`, the slots after them.
#[test]
fn schedule_v6_counts_the_centers_at_their_bound_where_the_contract_says() {
    let offsets = [
        offset_of!(Schedule, rank),
        offset_of!(Schedule, saturated),
        offset_of!(Schedule, at_bound),
        offset_of!(Schedule, reserved),
        offset_of!(Schedule, slots),
    ];
    assert_eq!(offsets, [80, 84, 88, 92, 96]);
    assert_eq!(size_of::<Schedule>(), 96 + ipc_types::MAX_SLOTS * 32);
    let s = Schedule::new();
    assert_eq!((s.saturated, s.at_bound, s.reserved), (0, 0, 0));
}

#[test]
fn a_new_part_is_a_point_and_the_builders_keep_its_pose() {
    let p = PartState::new(7, 1, 2, [0.1, -0.2, 0.3], [0.01, 0.02, 0.03]);
    assert_eq!((p.shape, p.radius, p.vertex_count, p.reserved), (SHAPE_POINT, 0.0, 0, 0));
    assert_eq!(p.vertices, [[0.0; 2]; MAX_SHAPE_VERTICES]);
    assert!(p.polygon().is_empty());
    assert_eq!(PartState::ZERO.shape, SHAPE_POINT);

    let d = p.with_disc(0.02);
    assert_eq!((d.shape, d.radius), (SHAPE_DISC, 0.02));
    assert_eq!(PartState { shape: SHAPE_POINT, radius: 0.0, ..d }, p, "only the outline changed");

    let tri = [[0.02, 0.0], [-0.01, 0.015], [-0.01, -0.015]];
    let t = p.with_polygon(&tri).expect("3 fit");
    assert_eq!((t.shape, t.vertex_count, t.polygon()), (SHAPE_POLYGON, 3, &tri[..]));
    assert_eq!(t.vertices[3..], [[0.0; 2]; MAX_SHAPE_VERTICES - 3], "unused vertices stay 0");
    assert_eq!((t.id, t.x, t.y, t.theta, t.omega), (7, 0.1, -0.2, 0.3, 0.03));
    let all = [[0.0; 2]; MAX_SHAPE_VERTICES];
    assert!(p.with_polygon(&all).is_ok(), "8 fit (validate judges them)");
    assert_eq!(p.with_polygon(&[[0.0; 2]; MAX_SHAPE_VERTICES + 1]), Err(ShapeError::VertexCount));
}

/// Every rejection kind answers the message published on its service:
/// the kind's service is the `WireMessage::SERVICE` of that message, one
/// of `service_names::ALL`, and the kind's name is that service's.
#[test]
fn each_rejected_kind_names_its_message_and_service() {
    use ipc_types::{PickCommand, RecipeCommand, RejectedKind, WireMessage};
    for k in RejectedKind::ALL {
        let (service, type_name) = match k {
            RejectedKind::PartStates => (PartStates::SERVICE, type_name::<PartStates>()),
            RejectedKind::ForceRequest => (ForceRequest::SERVICE, type_name::<ForceRequest>()),
            RejectedKind::ExplicitSchedule => (ExplicitSchedule::SERVICE, type_name::<ExplicitSchedule>()),
            RejectedKind::CoreCommand => (CoreCommand::SERVICE, type_name::<CoreCommand>()),
            RejectedKind::PickCommand => (PickCommand::SERVICE, type_name::<PickCommand>()),
            RejectedKind::RecipeCommand => (RecipeCommand::SERVICE, type_name::<RecipeCommand>()),
        };
        assert_eq!(k.service(), service, "{k:?}: {type_name}");
        assert!(service_names::ALL.contains(&service), "{service}");
        assert_eq!(service.strip_prefix("upm/"), Some(k.as_str()), "{k:?}");
        assert_eq!(RejectedKind::from_code(k.code()), Some(k));
    }
    assert_eq!(RejectedKind::from_code(RejectedKind::ALL.len() as u32), None);
}

/// A pick's bytes round-trip through the wire form, whatever they hold.
#[test]
fn a_pick_crosses_the_wire_as_its_32_bytes() {
    use ipc_types::{PickCommand, WireMessage};
    let m = PickCommand::new(5, 77, 3, 123_456);
    assert_eq!(m.as_bytes().len(), 32);
    assert_eq!(PickCommand::from_bytes(m.as_bytes()), Ok(m));
    assert_eq!(&m.as_bytes()[24..28], &77u32.to_ne_bytes(), "part_id at 24");
    let any = [0xA5u8; 32];
    assert_eq!(PickCommand::from_bytes(&any).map(|p| p.as_bytes().to_vec()), Ok(any.to_vec()));
    assert!(PickCommand::from_bytes(&any[..31]).is_err());
}

/// A recipe's bytes round-trip through the wire form, whatever they hold;
/// the path starts at 24.
#[test]
fn a_recipe_crosses_the_wire_as_its_264_bytes() {
    use ipc_types::{RECIPE_PATH_BYTES, RecipeCommand, WireMessage};
    let m = RecipeCommand::new("/srv/recipes/gears.toml", 3, 123_456).expect("absolute");
    assert_eq!(m.as_bytes().len(), 24 + RECIPE_PATH_BYTES);
    assert_eq!(RecipeCommand::from_bytes(m.as_bytes()), Ok(m));
    assert_eq!(&m.as_bytes()[4..8], &23u32.to_ne_bytes(), "path_len at 4");
    assert_eq!(&m.as_bytes()[24..47], b"/srv/recipes/gears.toml", "path at 24");
    assert!(m.as_bytes()[47..].iter().all(|&b| b == 0), "the rest 0");
    let any = [0xA5u8; 264];
    assert_eq!(RecipeCommand::from_bytes(&any).map(|p| p.as_bytes().to_vec()), Ok(any.to_vec()));
    assert!(RecipeCommand::from_bytes(&any[..263]).is_err());
}

/// A line status's bytes round-trip; its counters sit where the contract says.
#[test]
fn a_line_status_crosses_the_wire_as_its_120_bytes() {
    use ipc_types::{LineStatus, WireMessage};
    let mut m = LineStatus::new();
    (m.line_pid, m.seq, m.login_failures, m.recipes_refused) = (4242, 9, 3, 2);
    assert_eq!(m.as_bytes().len(), 120);
    assert_eq!(LineStatus::from_bytes(m.as_bytes()), Ok(m));
    let offsets = [
        offset_of!(LineStatus, opcua_sessions),
        offset_of!(LineStatus, login_failures),
        offset_of!(LineStatus, modbus_refused_connections),
        offset_of!(LineStatus, picks_sent),
        offset_of!(LineStatus, recipes_refused),
    ];
    assert_eq!(offsets, [24, 32, 88, 96, 112]);
    assert_eq!(&m.as_bytes()[32..40], &3u64.to_ne_bytes(), "login_failures at 32");
    let any = [0x5Au8; 120];
    assert_eq!(LineStatus::from_bytes(&any).map(|p| p.as_bytes().to_vec()), Ok(any.to_vec()));
    assert!(LineStatus::from_bytes(&any[..119]).is_err());
}
