//! validate() runs on the RT solver thread: it must not allocate, whether
//! the message is accepted or rejected (errors are `Copy`, names `'static`).
//! The only test in this binary, so nothing else allocates while counting.

mod common;

use std::hint::black_box;

use common::counting_allocator::count;
use ipc_types::{
    ExplicitSchedule, ExplicitSlot, ForceEntry, ForceRequest, MAX_SHAPE_VERTICES, PartState, PartStates,
    Schedule, ScheduleSlot, Telemetry, ValidationLimits,
};

#[test]
fn validate_never_allocates() {
    let limits = ValidationLimits::new([1.0, 1.0], 1_000_000);

    let (v, n) = count(|| black_box(vec![0u8; 32]));
    drop(v);
    assert_eq!(n, 1, "the counting allocator must see a known allocation");

    let mut parts = PartStates::new();
    let mut request = ForceRequest::new();
    let mut explicit = ExplicitSchedule::new();
    let mut schedule = Schedule::new();
    // Every outline: the polygon check is the longest walk.
    let octagon: [[f64; 2]; MAX_SHAPE_VERTICES] = core::array::from_fn(|k| {
        let a = core::f64::consts::TAU * k as f64 / MAX_SHAPE_VERTICES as f64;
        [0.02 * a.cos(), 0.02 * a.sin()]
    });
    for i in 0..PartStates::CAPACITY as u32 {
        let point = PartState::new(i, 0, 0, [0.5, 0.5, 0.0], [0.0; 3]);
        let part = match i % 3 {
            0 => point.with_polygon(&octagon).expect("8 fit"),
            1 => point,
            _ => point.with_disc(0.02),
        };
        parts.push(part).expect("within capacity");
        let entry = if i < 16 {
            ForceEntry::force_and_curl(i, [0.1, 0.1], 0.1)
        } else {
            ForceEntry::force(i, [0.1, 0.1])
        };
        request.push(entry).expect("within capacity");
    }
    for j in 0..ExplicitSchedule::CAPACITY as u32 {
        explicit.push(ExplicitSlot::new(j, 0.5)).expect("within capacity");
        schedule.push(ScheduleSlot::new(j, [2.0, 2.0], -0.5)).expect("within capacity");
    }
    let telemetry = Telemetry::new();
    let mut rig = ipc_types::RigInfo::new();
    (rig.slot_ticks, rig.cycle_period_ns, rig.tick_hz, rig.mu_m_g) = (40, 1, 10_000.0, 0.1);
    (rig.plate_half_extent, rig.k_max, rig.max_part_force_n) = ([1.0, 1.0], 0.95, 0.1);
    (rig.parts_max_age_ms, rig.request_max_age_ms) = (200.0, 200.0);
    for j in 0..ipc_types::MAX_CENTERS {
        rig.push(ipc_types::RigCenter { x: j as f64, y: 2.0, k_bound: 0.5 }).expect("within capacity");
    }
    // Full, so validate() walks every pose and pick.
    let mut feed = ipc_types::FeedStatus::new();
    (feed.time_s, feed.robot_busy_s, feed.stuck_after_s) = (60.0, 20.0, 120.0);
    for j in 0..ipc_types::MAX_PICK_POSES as u32 {
        let pose = ipc_types::PickPoseState {
            class: j,
            x: 0.1,
            y: 0.2,
            theta: 0.3,
            ..ipc_types::PickPoseState::ZERO
        };
        feed.push(pose).expect("within capacity");
    }
    for n in 1..=ipc_types::FEED_RECENT_PICKS as u64 + 1 {
        feed.push_pick(ipc_types::PickEvent { number: n, time_s: n as f64, ..ipc_types::PickEvent::ZERO });
    }
    let mut pick = ipc_types::PickCommand::new(ipc_types::MAX_PICK_POSES as u32 - 1, 7, 1, 1_000);
    // The longest path, multi-byte: the UTF-8 check walks every byte.
    let path = format!("/{}", "é".repeat((ipc_types::RECIPE_PATH_BYTES - 1) / 2));
    let mut recipe = ipc_types::RecipeCommand::new(&path, 1, 1_000).expect("fits");
    drop(path);
    let mut line = ipc_types::LineStatus::new();
    line.stamp_ns = 1_000;
    let mut bad_outline = parts;
    bad_outline.parts[PartStates::CAPACITY - 1].vertices.swap(1, 5); // a polygon, now not convex
    assert!(matches!(bad_outline.validate(&limits), Err(ipc_types::PartStatesError::Shape { .. })));

    let (ok, n) = count(|| {
        black_box(parts.validate(&limits)).is_ok()
            && black_box(request.validate(&limits)).is_ok()
            && black_box(explicit.validate(&limits)).is_ok()
            && black_box(schedule.validate(&limits)).is_ok()
            && black_box(telemetry.validate(&limits)).is_ok()
            && black_box(rig.validate(&limits)).is_ok()
            && black_box(feed.validate(&limits)).is_ok()
            && black_box(pick.validate(&limits)).is_ok()
            && black_box(recipe.validate(&limits)).is_ok()
            && black_box(recipe.path()).is_ok()
            && black_box(line.validate(&limits)).is_ok()
            && black_box(line.total_refusals()) == 0
    });
    assert!(ok, "full-capacity messages must be valid");
    assert_eq!(n, 0, "validate() of valid messages allocated");

    // Rejected at the last entry: the whole message is walked, then an error built.
    parts.parts[PartStates::CAPACITY - 1].id = 0;
    request.entries[PartStates::CAPACITY - 1].fx = f64::NAN;
    explicit.slots[ExplicitSchedule::CAPACITY - 1].k = 2.0;
    schedule.saturated = 7;
    rig.centers[ipc_types::MAX_CENTERS - 1].k_bound = 2.0;
    feed.poses[ipc_types::MAX_PICK_POSES - 1].theta = f64::NAN;
    pick.part_id = 0; // the last check
    recipe.path[0] = b'r'; // UTF-8 all through, then not absolute: the last check
    line.protocol_version = 5;
    let mut bad_telemetry = telemetry;
    bad_telemetry.latency.solver.p50_ns = 1;
    let (all_rejected, n) = count(|| {
        black_box(parts.validate(&limits)).is_err()
            && black_box(bad_outline.validate(&limits)).is_err()
            && black_box(request.validate(&limits)).is_err()
            && black_box(explicit.validate(&limits)).is_err()
            && black_box(schedule.validate(&limits)).is_err()
            && black_box(bad_telemetry.validate(&limits)).is_err()
            && black_box(rig.validate(&limits)).is_err()
            && black_box(feed.validate(&limits)).is_err()
            && black_box(pick.validate(&limits)).is_err()
            && black_box(recipe.validate(&limits)).is_err()
            && black_box(line.validate(&limits)).is_err()
    });
    assert!(all_rejected, "corrupted messages must be rejected");
    assert_eq!(n, 0, "validate() of rejected messages allocated");
}
