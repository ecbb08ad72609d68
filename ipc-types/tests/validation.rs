//! Each validate() accepts a good message and rejects every kind of bad one
//! with the error naming the right field and index.

use ipc_types::{
    CapacityError, CoreState, ExplicitSchedule, ExplicitScheduleError, ExplicitSlot, FEED_RECENT_PICKS,
    FeedStatus, FeedStatusError, ForceEntry, ForceRequest, ForceRequestError, HeaderError, LineStatus,
    LineStatusError, MAX_CENTERS, MAX_CURLS, MAX_PARTS, MAX_PICK_POSES, MAX_SHAPE_VERTICES, MAX_SLOTS,
    PROTOCOL_VERSION, PartState, PartStates, PartStatesError, PickCommand, PickCommandError, PickEvent,
    PickPoseState, RECIPE_PATH_BYTES, RecipeCommand, RecipeCommandError, RejectReason, RejectedKind,
    Rejection, RigCenter, RigInfo, RigInfoError, SHAPE_DISC, SHAPE_POINT, SHAPE_POLYGON, Schedule,
    ScheduleError, ScheduleSlot, ShapeError, Telemetry, TelemetryError, ValidationLimits,
};

const NOW: u64 = 5_000_000_000;

fn limits() -> ValidationLimits {
    let mut l = ValidationLimits::new([0.3, 0.2], NOW);
    l.center_count = 9;
    l.k_max = 0.95;
    l.part_class_count = 4;
    l.friction_class_count = 2;
    l
}

fn good_part_states() -> PartStates {
    let mut m = PartStates::new();
    m.seq = 7;
    m.stamp_ns = NOW - 2_000_000;
    for i in 0..5u32 {
        let x = -0.3 + 0.15 * f64::from(i); // reaches the +0.3 edge exactly
        m.push(PartState::new(10 + i, i % 4, i % 2, [x, -0.2, 0.1], [0.01, -0.02, 0.5]))
            .expect("within capacity");
    }
    m
}

fn good_force_request() -> ForceRequest {
    let mut m = ForceRequest::new();
    m.seq = 3;
    m.stamp_ns = NOW;
    m.deadline_ns = NOW + 50_000_000;
    m.push(ForceEntry::force(10, [0.01, -0.02])).expect("within capacity");
    m.push(ForceEntry::curl(11, -0.05)).expect("within capacity");
    m.push(ForceEntry::force_and_curl(12, [0.0, 0.0], 0.1)).expect("within capacity");
    m
}

fn good_explicit_schedule() -> ExplicitSchedule {
    let mut m = ExplicitSchedule::new();
    m.stamp_ns = NOW;
    for j in 0..9u32 {
        m.push(ExplicitSlot::new(j, 0.95 - 0.2 * f64::from(j))).expect("within capacity");
    }
    m
}

fn good_schedule() -> Schedule {
    let mut m = Schedule::new();
    m.stamp_ns = NOW;
    m.cycle = 42;
    m.solve_time_ns = 12_000;
    m.residual = 1e-12;
    m.condition = f64::INFINITY; // rank-deficient solves report +∞
    m.rank = 3;
    m.saturated = 1;
    m.at_bound = 1;
    for j in 0..4u32 {
        m.push(ScheduleSlot::new(j, [2.0, -1.0], -0.95 + 0.5 * f64::from(j))).expect("within capacity");
    }
    m
}

fn good_telemetry() -> Telemetry {
    let mut m = Telemetry::new();
    m.stamp_ns = NOW;
    m.set_core_state(CoreState::Hold);
    m.plate_theta = -1e-3;
    m.parts_age_ms = 12.5;
    m.counters.ticks = 1000;
    m.latency.solver.samples = 10;
    m.latency.solver.p50_ns = 5;
    m.latency.solver.p99_ns = 5;
    m.latency.solver.p999_ns = 9;
    m.latency.solver.max_ns = 9;
    m
}

#[test]
fn good_messages_are_accepted() {
    let l = limits();
    assert_eq!(good_part_states().validate(&l), Ok(()));
    assert_eq!(good_force_request().validate(&l), Ok(()));
    assert_eq!(good_explicit_schedule().validate(&l), Ok(()));
    assert_eq!(good_schedule().validate(&l), Ok(()));
    assert_eq!(good_telemetry().validate(&l), Ok(()));
    // Empty messages are fine where "nothing" is meaningful.
    assert_eq!(PartStates::new().validate(&l), Ok(()));
    assert_eq!(ForceRequest::new().validate(&l), Ok(()));
    assert_eq!(Telemetry::new().validate(&l), Ok(()));
}

#[test]
fn wrong_version_is_rejected_everywhere() {
    let l = limits();
    let bad = PROTOCOL_VERSION + 1;
    let mut p = good_part_states();
    p.protocol_version = bad;
    assert_eq!(
        p.validate(&l),
        Err(PartStatesError::Header(HeaderError::WrongProtocolVersion { found: bad }))
    );
    let mut f = good_force_request();
    f.protocol_version = 0;
    assert_eq!(
        f.validate(&l),
        Err(ForceRequestError::Header(HeaderError::WrongProtocolVersion { found: 0 }))
    );
    let mut e = good_explicit_schedule();
    e.protocol_version = bad;
    assert_eq!(
        e.validate(&l),
        Err(ExplicitScheduleError::Header(HeaderError::WrongProtocolVersion { found: bad }))
    );
    let mut s = good_schedule();
    s.protocol_version = bad;
    assert_eq!(s.validate(&l), Err(ScheduleError::Header(HeaderError::WrongProtocolVersion { found: bad })));
    let mut t = good_telemetry();
    t.protocol_version = bad;
    assert_eq!(t.validate(&l), Err(TelemetryError::Header(HeaderError::WrongProtocolVersion { found: bad })));
}

#[test]
fn count_beyond_capacity_is_rejected_and_accessors_clamp() {
    let l = limits();
    let mut p = good_part_states();
    p.count = MAX_PARTS as u32 + 1;
    assert_eq!(
        p.validate(&l),
        Err(PartStatesError::Header(HeaderError::CountExceedsCapacity {
            count: MAX_PARTS as u32 + 1,
            capacity: MAX_PARTS
        }))
    );
    p.count = u32::MAX;
    assert_eq!(p.parts().len(), MAX_PARTS);
    assert_eq!(p.push(PartState::ZERO), Err(CapacityError::Full { capacity: MAX_PARTS }));

    let mut f = good_force_request();
    f.count = u32::MAX;
    assert_eq!(
        f.validate(&l),
        Err(ForceRequestError::Header(HeaderError::CountExceedsCapacity {
            count: u32::MAX,
            capacity: MAX_PARTS
        }))
    );
    assert_eq!(f.entries().len(), MAX_PARTS);
    assert_eq!(f.entries_mut().len(), MAX_PARTS);

    let mut e = good_explicit_schedule();
    e.count = MAX_SLOTS as u32 + 1;
    assert_eq!(
        e.validate(&l),
        Err(ExplicitScheduleError::Header(HeaderError::CountExceedsCapacity {
            count: MAX_SLOTS as u32 + 1,
            capacity: MAX_SLOTS
        }))
    );
    assert_eq!(e.slots().len(), MAX_SLOTS);

    let mut s = good_schedule();
    s.count = 1 << 31;
    assert_eq!(
        s.validate(&l),
        Err(ScheduleError::Header(HeaderError::CountExceedsCapacity { count: 1 << 31, capacity: MAX_SLOTS }))
    );
    assert_eq!(s.slots().len(), MAX_SLOTS);
}

#[test]
fn exactly_full_messages_are_accepted() {
    let l = limits();
    let mut p = PartStates::new();
    for i in 0..MAX_PARTS as u32 {
        p.push(PartState::new(i, 0, 0, [0.0; 3], [0.0; 3])).expect("within capacity");
    }
    assert_eq!(p.push(PartState::ZERO), Err(CapacityError::Full { capacity: MAX_PARTS }));
    assert_eq!(p.validate(&l), Ok(()));

    let mut e = ExplicitSchedule::new();
    for j in 0..MAX_SLOTS as u32 {
        e.push(ExplicitSlot::new(j % 9, 0.0)).expect("within capacity");
    }
    assert_eq!(e.push(ExplicitSlot::ZERO), Err(CapacityError::Full { capacity: MAX_SLOTS }));
    assert_eq!(e.validate(&l), Ok(()));
}

#[test]
fn nan_and_inf_are_rejected_naming_the_field() {
    let l = limits();
    for (field, value) in [("x", f64::NAN), ("theta", f64::INFINITY), ("omega", f64::NEG_INFINITY)] {
        let mut p = good_part_states();
        let part = &mut p.parts_mut()[3];
        match field {
            "x" => part.x = value,
            "theta" => part.theta = value,
            _ => part.omega = value,
        }
        assert_eq!(p.validate(&l), Err(PartStatesError::NonFinite { index: 3, field }));
    }
    let mut f = good_force_request();
    f.entries_mut()[1].fy = f64::NAN; // checked even though only the curl is requested
    assert_eq!(f.validate(&l), Err(ForceRequestError::NonFinite { index: 1, field: "fy" }));
    let mut f = good_force_request();
    f.entries_mut()[2].curl = f64::INFINITY;
    assert_eq!(f.validate(&l), Err(ForceRequestError::NonFinite { index: 2, field: "curl" }));

    let mut e = good_explicit_schedule();
    e.slots_mut()[8].k = f64::NAN;
    assert_eq!(e.validate(&l), Err(ExplicitScheduleError::NonFinite { index: 8, field: "k" }));

    let mut s = good_schedule();
    s.slots_mut()[1].y = f64::NAN;
    assert_eq!(s.validate(&l), Err(ScheduleError::NonFinite { index: 1, field: "y" }));
    let mut s = good_schedule();
    s.residual = f64::INFINITY;
    assert_eq!(s.validate(&l), Err(ScheduleError::InvalidResidual));
    let mut s = good_schedule();
    s.condition = f64::NAN;
    assert_eq!(s.validate(&l), Err(ScheduleError::InvalidCondition));

    let mut t = good_telemetry();
    t.plate_y = f64::NAN;
    assert_eq!(t.validate(&l), Err(TelemetryError::NonFinite { field: "plate_y" }));
    let mut t = good_telemetry();
    t.request_age_ms = f64::INFINITY;
    assert_eq!(t.validate(&l), Err(TelemetryError::NonFinite { field: "request_age_ms" }));
}

#[test]
fn entries_beyond_count_are_ignored() {
    let l = limits();
    let mut p = good_part_states();
    p.parts[MAX_PARTS - 1].x = f64::NAN;
    p.parts[MAX_PARTS - 1].id = 10; // would duplicate parts[0]
    assert_eq!(p.validate(&l), Ok(()));
}

#[test]
fn off_plate_positions_are_rejected() {
    let l = limits();
    let mut p = good_part_states();
    p.parts_mut()[2].x = 0.3 + 1e-9;
    assert_eq!(p.validate(&l), Err(PartStatesError::OffPlate { index: 2, field: "x" }));
    let mut p = good_part_states();
    p.parts_mut()[4].y = -0.2 - 1e-9;
    assert_eq!(p.validate(&l), Err(PartStatesError::OffPlate { index: 4, field: "y" }));
    // A NaN bound rejects instead of accepting everything.
    let mut nan_limits = l;
    nan_limits.plate_half_extent_m[0] = f64::NAN;
    assert_eq!(
        good_part_states().validate(&nan_limits),
        Err(PartStatesError::OffPlate { index: 0, field: "x" })
    );
}

#[test]
fn duplicate_ids_are_rejected() {
    let l = limits();
    let mut p = good_part_states();
    p.parts_mut()[4].id = p.parts[1].id;
    assert_eq!(p.validate(&l), Err(PartStatesError::DuplicateId { index: 4, first_index: 1, id: 11 }));
    let mut f = good_force_request();
    f.entries_mut()[2].part_id = 10;
    assert_eq!(
        f.validate(&l),
        Err(ForceRequestError::DuplicatePartId { index: 2, first_index: 0, part_id: 10 })
    );
}

#[test]
fn future_stamps_are_rejected_within_skew_accepted() {
    let l = limits();
    let mut p = good_part_states();
    p.stamp_ns = NOW + l.max_future_skew_ns;
    assert_eq!(p.validate(&l), Ok(()));
    p.stamp_ns += 1;
    assert_eq!(
        p.validate(&l),
        Err(PartStatesError::Header(HeaderError::StampFromFuture { stamp_ns: p.stamp_ns, now_ns: NOW }))
    );

    let mut f = good_force_request();
    f.stamp_ns = u64::MAX;
    f.deadline_ns = u64::MAX;
    assert!(matches!(f.validate(&l), Err(ForceRequestError::Header(HeaderError::StampFromFuture { .. }))));
    let mut e = good_explicit_schedule();
    e.stamp_ns = NOW + 10_000_000;
    assert!(matches!(
        e.validate(&l),
        Err(ExplicitScheduleError::Header(HeaderError::StampFromFuture { .. }))
    ));
    let mut s = good_schedule();
    s.stamp_ns = NOW + 10_000_000;
    assert!(matches!(s.validate(&l), Err(ScheduleError::Header(HeaderError::StampFromFuture { .. }))));
    let mut t = good_telemetry();
    t.stamp_ns = NOW + 10_000_000;
    assert!(matches!(t.validate(&l), Err(TelemetryError::Header(HeaderError::StampFromFuture { .. }))));
    // now_ns near u64::MAX must not overflow into "everything is future".
    let mut late = l;
    late.now_ns = u64::MAX - 1;
    assert_eq!(good_part_states().validate(&late), Ok(()));
}

#[test]
fn unknown_classes_are_rejected() {
    let l = limits();
    let mut p = good_part_states();
    p.parts_mut()[0].class = 4;
    assert_eq!(p.validate(&l), Err(PartStatesError::UnknownClass { index: 0, class: 4 }));
    let mut p = good_part_states();
    p.parts_mut()[1].friction_class = 7;
    assert_eq!(p.validate(&l), Err(PartStatesError::UnknownFrictionClass { index: 1, friction_class: 7 }));
}

#[test]
fn force_request_flags_curls_and_deadline() {
    let l = limits();
    let mut f = good_force_request();
    f.entries_mut()[0].force_flag = 2;
    assert_eq!(f.validate(&l), Err(ForceRequestError::NotAFlag { index: 0, field: "force_flag", value: 2 }));
    let mut f = good_force_request();
    f.entries_mut()[1].curl_flag = u32::MAX;
    assert_eq!(
        f.validate(&l),
        Err(ForceRequestError::NotAFlag { index: 1, field: "curl_flag", value: u32::MAX })
    );
    let mut f = good_force_request();
    f.entries_mut()[1].curl_flag = 0;
    assert_eq!(f.validate(&l), Err(ForceRequestError::ConstrainsNothing { index: 1 }));
    let mut f = good_force_request();
    f.deadline_ns = f.stamp_ns - 1;
    assert!(matches!(f.validate(&l), Err(ForceRequestError::DeadlineBeforeStamp { .. })));

    // push refuses the 17th curl; a hand-written 17th curl fails validation.
    let mut f = ForceRequest::new();
    for id in 0..MAX_CURLS as u32 {
        f.push(ForceEntry::curl(id, 0.01)).expect("within capacity");
    }
    assert_eq!(f.curl_count(), MAX_CURLS);
    assert_eq!(f.push(ForceEntry::curl(99, 0.01)), Err(CapacityError::CurlsFull { capacity: MAX_CURLS }));
    f.push(ForceEntry::force(99, [0.0, 0.0])).expect("within capacity");
    assert_eq!(f.validate(&l), Ok(()));
    f.entries_mut()[MAX_CURLS].curl_flag = 1;
    assert_eq!(f.validate(&l), Err(ForceRequestError::TooManyCurls { index: MAX_CURLS }));

    let e = f.entries()[0];
    assert_eq!((e.requested_force(), e.requested_curl()), (None, Some(0.01)));
}

#[test]
fn schedules_check_centers_k_and_flags() {
    let l = limits();
    let mut e = good_explicit_schedule();
    e.slots_mut()[3].center_index = 9;
    assert_eq!(e.validate(&l), Err(ExplicitScheduleError::UnknownCenter { index: 3, center_index: 9 }));
    let mut e = good_explicit_schedule();
    e.slots_mut()[5].k = -0.951;
    assert_eq!(e.validate(&l), Err(ExplicitScheduleError::KOutOfRange { index: 5 }));
    let mut loose = l;
    loose.k_max = 7.0; // never above the physical bound 1
    let mut e = good_explicit_schedule();
    e.slots_mut()[0].k = 1.01;
    assert_eq!(e.validate(&loose), Err(ExplicitScheduleError::KOutOfRange { index: 0 }));
    assert_eq!(ExplicitSchedule::new().validate(&l), Err(ExplicitScheduleError::Empty));

    let mut s = good_schedule();
    s.saturated = 2;
    assert_eq!(s.validate(&l), Err(ScheduleError::NotAFlag { field: "saturated", value: 2 }));
    let mut s = good_schedule();
    s.residual = -1e-9;
    assert_eq!(s.validate(&l), Err(ScheduleError::InvalidResidual));
    let mut s = good_schedule();
    s.rank = MAX_SLOTS as u32 + 1;
    assert_eq!(s.validate(&l), Err(ScheduleError::RankExceedsCapacity { rank: MAX_SLOTS as u32 + 1 }));
    let mut s = good_schedule();
    s.slots_mut()[2].center_index = 100;
    assert_eq!(s.validate(&l), Err(ScheduleError::UnknownCenter { index: 2, center_index: 100 }));
    let mut s = good_schedule();
    s.slots_mut()[0].k = -0.96;
    assert_eq!(s.validate(&l), Err(ScheduleError::KOutOfRange { index: 0 }));
    assert!(good_schedule().is_saturated());
    let mut s = good_schedule();
    s.at_bound = MAX_CENTERS as u32;
    assert_eq!(s.validate(&l), Ok(()));
    s.at_bound += 1;
    assert_eq!(
        s.validate(&l),
        Err(ScheduleError::AtBoundExceedsCapacity { at_bound: MAX_CENTERS as u32 + 1 })
    );
    assert_eq!(
        s.validate(&l).expect_err("too many").to_string(),
        "schedule.at_bound 193 exceeds the capacity 192"
    );
}

fn good_rig_info() -> RigInfo {
    let mut m = RigInfo::new();
    m.seq = 1;
    m.stamp_ns = NOW;
    m.core_pid = 42;
    m.slot_ticks = 40;
    m.cycle_period_ns = 16_000_000;
    m.tick_hz = 10_000.0;
    m.vision_frame_hz = 30.0;
    m.mu_m_g = 0.1;
    m.plate_half_extent = [0.2, 0.15];
    m.k_max = 0.95;
    m.max_part_force_n = 0.05;
    m.keep_out_m = 0.1;
    m.saturation_tolerance = 1e-3;
    m.saturation_floor = 1e-12;
    m.parts_max_age_ms = 200.0;
    m.request_max_age_ms = 200.0;
    m.max_future_skew_ms = 1.0;
    m.set_prefix("upm_");
    for (j, c) in [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]].iter().enumerate() {
        m.push(RigCenter { x: c[0], y: c[1], k_bound: 0.95 - 0.1 * j as f64 }).expect("within capacity");
    }
    m
}

#[test]
fn rig_info_is_checked_field_by_field_and_old_stamps_are_fine() {
    let l = limits();
    assert_eq!(good_rig_info().validate(&l), Ok(()));
    let mut old = good_rig_info();
    old.stamp_ns = 1;
    assert_eq!(old.validate(&l), Ok(()), "published once at start: any age");
    // How to break a good one, what validate() says, and its line.
    type Case = (fn(&mut RigInfo), RigInfoError, &'static str);
    let cases: [Case; 8] = [
        (
            |m| m.protocol_version = 5,
            RigInfoError::Header(HeaderError::WrongProtocolVersion { found: 5 }),
            "rig_info.protocol_version is 5, expected 6",
        ),
        (
            |m| m.mu_m_g = f64::NAN,
            RigInfoError::NonFinite { field: "mu_m_g" },
            "rig_info.mu_m_g is not finite",
        ),
        (
            |m| m.plate_half_extent[1] = 0.0,
            RigInfoError::NotPositive { field: "plate_half_extent" },
            "rig_info.plate_half_extent must be positive",
        ),
        (|m| m.count = 0, RigInfoError::NotPositive { field: "count" }, "rig_info.count must be positive"),
        (|m| m.k_max = 1.0, RigInfoError::KMax, "rig_info.k_max must be in (0, 1)"),
        (
            |m| m.cycle_slots = 193,
            RigInfoError::CycleSlots { slots: 193 },
            "rig_info.cycle_slots 193 exceeds the capacity 192",
        ),
        (
            |m| m.centers[2].y = f64::INFINITY,
            RigInfoError::CenterNonFinite { index: 2 },
            "rig_info.centers[2] is not finite",
        ),
        (
            |m| m.centers[3].k_bound = 0.96,
            RigInfoError::KBound { index: 3 },
            "rig_info.centers[3].k_bound must be in (0, k_max]",
        ),
    ];
    for (break_it, want, text) in cases {
        let mut m = good_rig_info();
        break_it(&mut m);
        assert_eq!(m.validate(&l), Err(want));
        assert_eq!(want.to_string(), text);
    }
    let mut m = good_rig_info();
    m.count = u32::MAX;
    assert!(matches!(m.validate(&l), Err(RigInfoError::Header(HeaderError::CountExceedsCapacity { .. }))));
    assert_eq!(m.centers().len(), MAX_CENTERS, "a corrupt count is clamped");
}

fn good_feed_status() -> FeedStatus {
    let mut m = FeedStatus::new();
    m.seq = 12;
    m.stamp_ns = NOW;
    (m.arrived, m.picked, m.lost, m.arrivals_blocked) = (40, 30, 2, 5);
    (m.on_plate, m.stuck) = (8, 1);
    (m.time_s, m.robot_busy_s, m.stuck_after_s) = (600.0, 250.0, 120.0);
    for j in 0..3u32 {
        let pose = PickPoseState { class: j, part_id: 0, ready: 0, reserved: 0, x: 0.1, y: -0.1, theta: 0.5 };
        m.push(pose).expect("within capacity");
    }
    m.poses_mut()[1].part_id = 17;
    m.poses_mut()[1].ready = 1;
    for n in 1..=3u64 {
        let pick = PickEvent {
            number: n,
            part_id: 10 + n as u32,
            class: 1,
            pose: 2,
            time_s: 100.0 * n as f64,
            position_error_m: 1e-3,
            angle_error_rad: -0.01,
            on_plate_s: 30.0,
            ..PickEvent::ZERO
        };
        m.push_pick(pick);
    }
    m
}

#[test]
fn feed_status_is_checked_field_by_field_and_old_stamps_are_fine() {
    let l = limits();
    assert_eq!(good_feed_status().validate(&l), Ok(()));
    assert_eq!(FeedStatus::new().validate(&l), Ok(()), "nothing yet is a valid status");
    let mut old = good_feed_status();
    old.stamp_ns = 1;
    assert_eq!(old.validate(&l), Ok(()), "a core output: any age");
    // How to break a good one, what validate() says, and its line.
    type Case = (fn(&mut FeedStatus), FeedStatusError, &'static str);
    let cases: [Case; 8] = [
        (
            |m| m.protocol_version = 5,
            FeedStatusError::Header(HeaderError::WrongProtocolVersion { found: 5 }),
            "feed_status.protocol_version is 5, expected 6",
        ),
        (
            |m| m.count = MAX_PICK_POSES as u32 + 1,
            FeedStatusError::Header(HeaderError::CountExceedsCapacity {
                count: 17,
                capacity: MAX_PICK_POSES,
            }),
            "feed_status.count 17 exceeds the capacity 16",
        ),
        (
            |m| m.stamp_ns = NOW + 1_000_000_000,
            FeedStatusError::Header(HeaderError::StampFromFuture {
                stamp_ns: NOW + 1_000_000_000,
                now_ns: NOW,
            }),
            "feed_status.stamp_ns 6000000000 is in the future (now 5000000000)",
        ),
        (
            |m| m.recent_count = FEED_RECENT_PICKS as u32 + 1,
            FeedStatusError::RecentCount { count: 17 },
            "feed_status.recent_count 17 exceeds the capacity 16",
        ),
        (
            |m| m.robot_busy_s = f64::INFINITY,
            FeedStatusError::NonFinite { field: "robot_busy_s" },
            "feed_status.robot_busy_s is not finite",
        ),
        (
            |m| m.stuck_after_s = f64::NAN,
            FeedStatusError::NonFinite { field: "stuck_after_s" },
            "feed_status.stuck_after_s is not finite",
        ),
        (
            |m| m.recent[2].position_error_m = f64::NEG_INFINITY,
            FeedStatusError::NonFinite { field: "recent.position_error_m" },
            "feed_status.recent.position_error_m is not finite",
        ),
        (
            |m| m.poses[1].theta = f64::NAN,
            FeedStatusError::NonFinite { field: "poses.theta" },
            "feed_status.poses.theta is not finite",
        ),
    ];
    for (break_it, want, text) in cases {
        let mut m = good_feed_status();
        break_it(&mut m);
        assert_eq!(m.validate(&l), Err(want));
        assert_eq!(want.to_string(), text);
    }
    // Entries past either count are not read.
    let mut m = good_feed_status();
    m.recent[3].time_s = f64::NAN;
    m.poses[3].x = f64::NAN;
    assert_eq!(m.validate(&l), Ok(()));
    // A corrupt count is clamped by the accessors.
    (m.count, m.recent_count) = (u32::MAX, u32::MAX);
    assert_eq!((m.poses().len(), m.recent().len()), (MAX_PICK_POSES, FEED_RECENT_PICKS));
    assert!(matches!(m.validate(&l), Err(FeedStatusError::Header(HeaderError::CountExceedsCapacity { .. }))));
    m.count = 0;
    assert_eq!(m.validate(&l), Err(FeedStatusError::RecentCount { count: u32::MAX }));
    m.push_pick(PickEvent { number: 99, ..PickEvent::ZERO });
    assert_eq!(m.recent().len(), FEED_RECENT_PICKS, "a full ring keeps its size");
    assert_eq!(m.recent().last().map(|p| p.number), Some(99));
}

fn good_pick_command() -> PickCommand {
    PickCommand::new(MAX_PICK_POSES as u32 - 1, 17, 9, NOW - 1_000_000)
}

#[test]
fn pick_command_is_checked_field_by_field_and_answered_as_a_pick() {
    let mut l = limits();
    assert_eq!(good_pick_command().validate(&l), Ok(()));
    assert_eq!(PickCommand::new(0, u32::MAX, 0, NOW).validate(&l), Ok(()), "any part but 0, pose 0");
    let mut future = good_pick_command();
    future.stamp_ns = NOW + l.max_future_skew_ns;
    assert_eq!(future.validate(&l), Ok(()), "within the skew");
    // Not a core output: an old stamp is refused once the receiver bounds the age.
    l.max_age_ns = 500_000;
    assert_eq!(
        good_pick_command().validate(&l),
        Err(PickCommandError::Header(HeaderError::Stale { stamp_ns: NOW - 1_000_000, now_ns: NOW }))
    );
    let l = limits();
    // How to break a good one, what validate() says, its reason and its line.
    type Case = (fn(&mut PickCommand), PickCommandError, RejectReason, &'static str);
    let cases: [Case; 5] = [
        (
            |m| m.protocol_version = 5,
            PickCommandError::Header(HeaderError::WrongProtocolVersion { found: 5 }),
            RejectReason::WrongProtocolVersion,
            "pick_command.protocol_version is 5, expected 6",
        ),
        (
            |m| m.stamp_ns = NOW + 1_000_001,
            PickCommandError::Header(HeaderError::StampFromFuture { stamp_ns: NOW + 1_000_001, now_ns: NOW }),
            RejectReason::StampFromFuture,
            "pick_command.stamp_ns 5001000001 is in the future (now 5000000000)",
        ),
        (
            |m| m.pose = MAX_PICK_POSES as u32,
            PickCommandError::PoseOutOfRange { pose: 16 },
            RejectReason::CountExceedsCapacity,
            "pick_command.pose 16 is not below the capacity 16",
        ),
        (
            |m| m.pose = u32::MAX,
            PickCommandError::PoseOutOfRange { pose: u32::MAX },
            RejectReason::CountExceedsCapacity,
            "pick_command.pose 4294967295 is not below the capacity 16",
        ),
        (
            |m| m.part_id = 0,
            PickCommandError::NoPart,
            RejectReason::UnknownPart,
            "pick_command.part_id is 0: no part",
        ),
    ];
    for (break_it, want, reason, text) in cases {
        let mut m = good_pick_command();
        break_it(&mut m);
        assert_eq!(m.validate(&l), Err(want));
        assert_eq!(want.reason(), reason, "{want:?}");
        assert_eq!(want.to_string(), text);
        // The answer on upm/rejection names the pick and carries the line.
        let r = Rejection::new(
            RejectedKind::PickCommand,
            m.seq,
            m.stamp_ns,
            NOW,
            want.reason(),
            format_args!("{want}"),
        );
        assert_eq!(
            (r.kind(), r.reason(), r.detail_str()),
            (Some(RejectedKind::PickCommand), Some(reason), text)
        );
        assert_eq!(r.to_string(), format!("pick seq 9 rejected: {} ({text})", reason.as_str()));
    }
    // The header is checked first: a wrong version hides the rest.
    let mut m = PickCommand::new(u32::MAX, 0, 1, NOW);
    m.protocol_version = 0;
    assert!(matches!(
        m.validate(&l),
        Err(PickCommandError::Header(HeaderError::WrongProtocolVersion { .. }))
    ));
}

fn good_recipe_command() -> RecipeCommand {
    RecipeCommand::new("/srv/upm/recipes/gears-m3.toml", 4, NOW - 1_000_000).expect("absolute, short")
}

#[test]
fn recipe_command_is_checked_field_by_field_and_answered_as_a_recipe() {
    let mut l = limits();
    assert_eq!(good_recipe_command().validate(&l), Ok(()));
    assert_eq!(good_recipe_command().path(), Ok("/srv/upm/recipes/gears-m3.toml"));
    let full = format!("/{}", "ü".repeat((RECIPE_PATH_BYTES - 2) / 2));
    let m = RecipeCommand::new(&full, 0, NOW).expect("240 bytes fit");
    assert_eq!((m.path_len as usize, m.validate(&l)), (RECIPE_PATH_BYTES - 1, Ok(())));
    assert_eq!(RecipeCommand::new("/", 0, NOW).map(|m| m.validate(&l)), Ok(Ok(())), "the root is absolute");
    let mut future = good_recipe_command();
    future.stamp_ns = NOW + l.max_future_skew_ns;
    assert_eq!(future.validate(&l), Ok(()), "within the skew");
    // Not an output: an old stamp is refused once the receiver bounds the age.
    l.max_age_ns = 500_000;
    assert_eq!(
        good_recipe_command().validate(&l),
        Err(RecipeCommandError::Header(HeaderError::Stale { stamp_ns: NOW - 1_000_000, now_ns: NOW }))
    );
    let l = limits();
    // How to break a good one, what validate() says, its reason and its line.
    type Case = (fn(&mut RecipeCommand), RecipeCommandError, RejectReason, &'static str);
    let cases: [Case; 7] = [
        (
            |m| m.protocol_version = 5,
            RecipeCommandError::Header(HeaderError::WrongProtocolVersion { found: 5 }),
            RejectReason::WrongProtocolVersion,
            "recipe_command.protocol_version is 5, expected 6",
        ),
        (
            |m| m.stamp_ns = NOW + 1_000_001,
            RecipeCommandError::Header(HeaderError::StampFromFuture {
                stamp_ns: NOW + 1_000_001,
                now_ns: NOW,
            }),
            RejectReason::StampFromFuture,
            "recipe_command.stamp_ns 5001000001 is in the future (now 5000000000)",
        ),
        (
            |m| m.path_len = RECIPE_PATH_BYTES as u32 + 1,
            RecipeCommandError::PathTooLong { len: 241 },
            RejectReason::CountExceedsCapacity,
            "recipe_command.path_len 241 exceeds the capacity 240",
        ),
        (
            |m| m.path_len = u32::MAX,
            RecipeCommandError::PathTooLong { len: u32::MAX },
            RejectReason::CountExceedsCapacity,
            "recipe_command.path_len 4294967295 exceeds the capacity 240",
        ),
        (
            |m| m.path[5] = 0xC3, // a lead byte followed by ASCII
            RecipeCommandError::NotUtf8,
            RejectReason::BadPath,
            "recipe_command.path is not UTF-8",
        ),
        (
            |m| m.path[0] = b'~',
            RecipeCommandError::NotAbsolute,
            RejectReason::BadPath,
            "recipe_command.path is not absolute: it must start with '/'",
        ),
        (
            |m| m.path_len = 0,
            RecipeCommandError::NotAbsolute,
            RejectReason::BadPath,
            "recipe_command.path is not absolute: it must start with '/'",
        ),
    ];
    for (break_it, want, reason, text) in cases {
        let mut m = good_recipe_command();
        break_it(&mut m);
        assert_eq!(m.validate(&l), Err(want));
        assert_eq!(want.reason(), reason, "{want:?}");
        assert_eq!(want.to_string(), text);
        // The answer on upm/rejection names the recipe and carries the line.
        let r = Rejection::new(
            RejectedKind::RecipeCommand,
            m.seq,
            m.stamp_ns,
            NOW,
            want.reason(),
            format_args!("{want}"),
        );
        assert_eq!(
            (r.kind(), r.reason(), r.detail_str()),
            (Some(RejectedKind::RecipeCommand), Some(reason), text)
        );
        assert_eq!(r.to_string(), format!("recipe seq 4 rejected: {} ({text})", reason.as_str()));
    }
    // Bytes past path_len are not read: a path cut short is still checked as cut.
    let mut m = good_recipe_command();
    m.path[m.path_len as usize] = 0xFF;
    m.path[RECIPE_PATH_BYTES - 1] = 0xFF;
    assert_eq!(m.validate(&l), Ok(()));
    // The header is checked first: a wrong version hides the rest.
    let mut m = good_recipe_command();
    (m.protocol_version, m.path_len) = (0, u32::MAX);
    assert!(matches!(
        m.validate(&l),
        Err(RecipeCommandError::Header(HeaderError::WrongProtocolVersion { .. }))
    ));
    // new() refuses what validate() would.
    let over = format!("/{}", "a".repeat(RECIPE_PATH_BYTES));
    assert_eq!(RecipeCommand::new(&over, 1, NOW), Err(RecipeCommandError::PathTooLong { len: 241 }));
    assert_eq!(RecipeCommand::new("recipes/gears.toml", 1, NOW), Err(RecipeCommandError::NotAbsolute));
}

#[test]
fn line_status_checks_its_header_only_and_old_stamps_are_fine() {
    let mut l = limits();
    let mut m = LineStatus::new();
    (m.line_pid, m.seq, m.stamp_ns) = (4242, 17, NOW - 4_000_000_000);
    (m.login_failures, m.modbus_refused_connections, m.picks_sent) = (3, u64::MAX, 9);
    assert_eq!(m.validate(&l), Ok(()));
    l.max_age_ns = 1;
    assert_eq!(m.validate(&l), Ok(()), "an output: any age");
    assert_eq!(m.total_refusals(), u64::MAX, "saturates");
    m.stamp_ns = NOW + 1_000_001;
    assert_eq!(
        m.validate(&l),
        Err(LineStatusError::Header(HeaderError::StampFromFuture { stamp_ns: NOW + 1_000_001, now_ns: NOW }))
    );
    m.protocol_version = 7;
    let e = m.validate(&l).expect_err("wrong version");
    assert_eq!(e, LineStatusError::Header(HeaderError::WrongProtocolVersion { found: 7 }));
    assert_eq!(e.to_string(), "line_status.protocol_version is 7, expected 6");
    let names: Vec<&str> = LineStatus::new().refusals().iter().map(|(n, _)| *n).collect();
    assert_eq!(
        names,
        [
            "login_failures",
            "access_denied",
            "bad_arguments",
            "invalid_state",
            "failed_calls",
            "modbus_exceptions",
            "modbus_bad_frames",
            "modbus_refused_connections"
        ]
    );
}

#[test]
fn telemetry_state_ages_and_percentiles() {
    let l = limits();
    let mut t = good_telemetry();
    assert_eq!(t.core_state(), Some(CoreState::Hold));
    t.state = 4;
    assert_eq!(t.validate(&l), Err(TelemetryError::UnknownState { code: 4 }));
    assert_eq!(t.core_state(), None);
    let mut t = good_telemetry();
    t.parts_age_ms = -0.5;
    assert_eq!(t.validate(&l), Err(TelemetryError::NegativeAge { field: "parts_age_ms" }));
    let mut t = good_telemetry();
    t.latency.frame_to_schedule.p99_ns = 10;
    assert_eq!(t.validate(&l), Err(TelemetryError::UnorderedPercentiles { field: "frame_to_schedule" }));
    for state in [CoreState::Idle, CoreState::Running, CoreState::Hold, CoreState::Fault] {
        assert_eq!(CoreState::from_code(state.code()), Some(state));
    }
    assert_eq!(CoreState::Running.to_string(), "running");
}

#[test]
fn errors_display_the_offending_field() {
    let l = limits();
    let mut p = good_part_states();
    p.parts_mut()[3].vy = f64::NAN;
    let msg = p.validate(&l).expect_err("must be rejected").to_string();
    assert_eq!(msg, "part_states.parts[3].vy is not finite");
    let mut p = good_part_states();
    p.parts_mut()[3] = p.parts[3].with_disc(f64::NAN);
    let msg = p.validate(&l).expect_err("must be rejected").to_string();
    assert_eq!(msg, "part_states.parts[3].radius: radius must be a finite number ≥ 0.0001 m");
    let mut f = good_force_request();
    f.entries_mut()[2].part_id = 11;
    let msg = f.validate(&l).expect_err("must be rejected").to_string();
    assert_eq!(msg, "force_request.entries[2].part_id 11 duplicates entries[1]");
    // Errors are usable as `dyn Error`.
    let boxed: Box<dyn std::error::Error> = Box::new(ScheduleError::InvalidCondition);
    assert!(boxed.to_string().contains("schedule.condition"));
}

// --- Part outlines ------------------------------------------------------

const SQUARE: [[f64; 2]; 4] = [[0.01, 0.01], [-0.01, 0.01], [-0.01, -0.01], [0.01, -0.01]];
const TRIANGLE: [[f64; 2]; 3] = [[0.02, 0.0], [-0.01, 0.015], [-0.01, -0.015]];

/// good_part_states() with parts[3] changed by `f`.
fn with_part_3(f: impl FnOnce(&mut PartState)) -> PartStates {
    let mut m = good_part_states();
    f(&mut m.parts_mut()[3]);
    m
}

fn code(shape: u32) -> impl FnOnce(&mut PartState) {
    move |p: &mut PartState| p.shape = shape
}

fn disc(radius: f64) -> impl FnOnce(&mut PartState) {
    move |p: &mut PartState| *p = p.with_disc(radius)
}

fn polygon(vertices: &[[f64; 2]]) -> impl FnOnce(&mut PartState) + '_ {
    move |p: &mut PartState| {
        *p = p.with_polygon(vertices).expect("at most 8 vertices");
    }
}

/// A square whose `vertex_count` is then overwritten with `n`.
fn polygon_of_count(n: u32) -> impl FnOnce(&mut PartState) {
    move |p: &mut PartState| {
        *p = p.with_polygon(&SQUARE).expect("4 fit");
        p.vertex_count = n;
    }
}

/// A rejection of parts[3] must be a `Shape` error counted as `bad_shape`
/// whose one line names `field` and reaches the sender whole.
fn assert_bad_shape(m: &PartStates, error: ShapeError, field: &str, label: &str) {
    let got = m.validate(&limits());
    assert_eq!(got, Err(PartStatesError::Shape { index: 3, error }), "{label}");
    let e = got.expect_err("checked above");
    assert_eq!(e.reason(), RejectReason::BadShape, "{label}");
    assert_eq!(e.reason().as_str(), "bad_shape");
    let line = e.to_string();
    assert_eq!(line, format!("part_states.parts[3].{field}: {error}"), "{label}");
    assert!(!line.contains('\n'), "{label}: {line:?} is not one line");
    let r = Rejection::new(RejectedKind::PartStates, 1, 2, 3, e.reason(), format_args!("{e}"));
    assert_eq!(r.detail_str(), line, "{label}: cut in the Rejection");
}

#[test]
fn every_shape_error_names_its_field_and_counts_as_bad_shape() {
    let mut bowtie = SQUARE;
    bowtie.swap(1, 2);
    // A concave "dart": turns both ways.
    let dart = [[0.02, 0.0], [-0.01, 0.015], [0.0, 0.0], [-0.01, -0.015]];
    // A pentagram: turns one way only, but twice round.
    let star: Vec<[f64; 2]> = (0..5)
        .map(|k| {
            let a = core::f64::consts::TAU * f64::from(2 * k) / 5.0;
            [0.02 * a.cos(), 0.02 * a.sin()]
        })
        .collect();
    let repeated = [[0.01, 0.01], [0.01, 0.01], [-0.01, 0.01], [-0.01, -0.01]];
    let collinear = [[0.0, 0.0], [0.01, 0.0], [0.02, 0.0]];
    let on_an_edge = [[0.01, 0.0], [0.0, 0.01], [-0.01, 0.0], [0.0, 0.0], [0.0, -0.01]];
    let beyond_the_plate = [[0.31, 0.0], [0.0, 0.01], [0.0, -0.01]]; // limits(): extent 0.3

    type Case<'a> = (&'a str, Box<dyn FnOnce(&mut PartState) + 'a>, ShapeError, &'a str);
    let cases: Vec<Case> = vec![
        ("shape 3", Box::new(code(3)), ShapeError::Code, "shape"),
        ("shape u32::MAX", Box::new(code(u32::MAX)), ShapeError::Code, "shape"),
        ("radius 0", Box::new(disc(0.0)), ShapeError::Radius, "radius"),
        ("radius -0", Box::new(disc(-0.0)), ShapeError::Radius, "radius"),
        ("radius < 0", Box::new(disc(-0.01)), ShapeError::Radius, "radius"),
        ("radius NaN", Box::new(disc(f64::NAN)), ShapeError::Radius, "radius"),
        ("radius inf", Box::new(disc(f64::INFINITY)), ShapeError::Radius, "radius"),
        ("radius -inf", Box::new(disc(f64::NEG_INFINITY)), ShapeError::Radius, "radius"),
        ("vertex_count 0", Box::new(polygon_of_count(0)), ShapeError::VertexCount, "vertex_count"),
        ("vertex_count 2", Box::new(polygon_of_count(2)), ShapeError::VertexCount, "vertex_count"),
        ("vertex_count 9", Box::new(polygon_of_count(9)), ShapeError::VertexCount, "vertex_count"),
        ("vertex_count MAX", Box::new(polygon_of_count(u32::MAX)), ShapeError::VertexCount, "vertex_count"),
        (
            "a NaN vertex",
            Box::new(|p: &mut PartState| {
                *p = p.with_polygon(&SQUARE).expect("4 fit");
                p.vertices[2][1] = f64::NAN;
            }),
            ShapeError::NonFinite,
            "vertices",
        ),
        (
            "an infinite vertex",
            Box::new(|p: &mut PartState| {
                *p = p.with_polygon(&TRIANGLE).expect("3 fit");
                p.vertices[0][0] = f64::NEG_INFINITY;
            }),
            ShapeError::NonFinite,
            "vertices",
        ),
        ("a bow-tie", Box::new(polygon(&bowtie)), ShapeError::NotConvex, "vertices"),
        ("a dart", Box::new(polygon(&dart)), ShapeError::NotConvex, "vertices"),
        ("a pentagram", Box::new(polygon(&star)), ShapeError::NotConvex, "vertices"),
        ("a repeated vertex", Box::new(polygon(&repeated)), ShapeError::NotConvex, "vertices"),
        ("three on a line", Box::new(polygon(&collinear)), ShapeError::NotConvex, "vertices"),
        ("a vertex on an edge", Box::new(polygon(&on_an_edge)), ShapeError::NotConvex, "vertices"),
        (
            "a polygon beyond the plate",
            Box::new(polygon(&beyond_the_plate)),
            ShapeError::VertexTooFar,
            "vertices",
        ),
    ];
    for (label, spoil, error, field) in cases {
        assert_bad_shape(&with_part_3(spoil), error, field, label);
    }
}

/// A disc too large is about its `radius`, not its (unused) `vertices`.
#[test]
fn a_disc_larger_than_the_plate_names_its_radius() {
    let m = with_part_3(disc(0.3 + 1e-9));
    assert_bad_shape(&m, ShapeError::RadiusTooLarge, "radius", "a disc beyond the plate");
}

#[test]
fn discs_squares_and_triangles_pass_in_either_winding() {
    let l = limits();
    assert_eq!(l.max_part_extent(), 0.3, "the larger half extent");
    let mut cw_square = SQUARE;
    cw_square.reverse();
    let mut cw_triangle = TRIANGLE;
    cw_triangle.reverse();
    let octagon: Vec<[f64; 2]> = (0..MAX_SHAPE_VERTICES)
        .map(|k| {
            let a = core::f64::consts::TAU * k as f64 / MAX_SHAPE_VERTICES as f64;
            [0.02 * a.cos(), 0.02 * a.sin()]
        })
        .collect();
    // Off-centre: the position need not be inside the outline.
    let off_centre = [[0.05, 0.05], [0.07, 0.05], [0.06, 0.07]];
    let mut m = good_part_states();
    let parts = m.parts_mut();
    parts[0] = parts[0].with_disc(0.01);
    parts[1] = parts[1].with_polygon(&SQUARE).expect("4 fit");
    parts[2] = parts[2].with_polygon(&cw_square).expect("4 fit");
    parts[3] = parts[3].with_polygon(&TRIANGLE).expect("3 fit");
    parts[4] = parts[4].with_polygon(&cw_triangle).expect("3 fit");
    assert_eq!(m.validate(&l), Ok(()));
    let parts = m.parts_mut();
    parts[0] = parts[0].with_polygon(&octagon).expect("8 fit");
    // Larger than the y half extent (0.2), within the x one (0.3).
    parts[1] = PartState { shape: SHAPE_DISC, radius: 0.25, ..parts[1] };
    parts[2] = parts[2].with_disc(0.3); // exactly the bound
    parts[3] = parts[3].with_polygon(&off_centre).expect("3 fit");
    assert_eq!(m.validate(&l), Ok(()));
    assert_eq!(m.parts()[0].polygon(), &octagon[..]);
    assert_eq!((m.parts()[0].shape, m.parts()[0].vertex_count), (SHAPE_POLYGON, 8));
}

#[test]
fn a_vertex_count_beyond_the_array_is_refused_without_panicking() {
    let l = limits();
    let nine = [[0.0; 2]; MAX_SHAPE_VERTICES + 1];
    assert_eq!(PartState::ZERO.with_polygon(&nine), Err(ShapeError::VertexCount));
    for n in [9, 64, 1 << 31, u32::MAX] {
        let m = with_part_3(polygon_of_count(n));
        assert_eq!(m.parts()[3].polygon().len(), MAX_SHAPE_VERTICES, "vertex_count {n} clamped");
        assert_eq!(
            m.validate(&l),
            Err(PartStatesError::Shape { index: 3, error: ShapeError::VertexCount }),
            "vertex_count {n}"
        );
    }
}

#[test]
fn fields_a_shape_does_not_use_are_ignored() {
    let l = limits();
    let garbage = |p: &mut PartState| {
        p.radius = f64::NAN;
        p.vertex_count = u32::MAX;
        p.vertices = [[f64::NAN, f64::INFINITY]; MAX_SHAPE_VERTICES];
    };
    // A point: radius, vertex_count and vertices are not read.
    let m = with_part_3(garbage);
    assert_eq!(m.parts()[3].shape, SHAPE_POINT);
    assert_eq!(m.validate(&l), Ok(()));
    // A disc: vertex_count and vertices are not read.
    let m = with_part_3(|p| {
        garbage(p);
        *p = p.with_disc(0.02);
    });
    assert_eq!(m.validate(&l), Ok(()));
    // A polygon: radius and the vertices past vertex_count are not read.
    let m = with_part_3(|p| {
        garbage(p);
        *p = p.with_polygon(&TRIANGLE).expect("3 fit");
    });
    assert!(m.parts()[3].vertices[3][0].is_nan());
    assert_eq!(m.validate(&l), Ok(()));
    // Parts past count are not read at all.
    let mut m = good_part_states();
    m.parts[MAX_PARTS - 1].shape = u32::MAX;
    assert_eq!(m.validate(&l), Ok(()));
}

#[test]
fn the_outline_is_checked_after_classes_and_before_duplicate_ids() {
    let l = limits();
    let m = with_part_3(|p| {
        p.shape = 7;
        p.class = 4;
    });
    assert_eq!(m.validate(&l), Err(PartStatesError::UnknownClass { index: 3, class: 4 }));
    let m = with_part_3(|p| {
        p.shape = 7;
        p.x = f64::NAN;
    });
    assert_eq!(m.validate(&l), Err(PartStatesError::NonFinite { index: 3, field: "x" }));
    let m = with_part_3(|p| {
        *p = p.with_disc(-1.0);
        p.id = 10; // duplicates parts[0]
    });
    assert_eq!(m.validate(&l), Err(PartStatesError::Shape { index: 3, error: ShapeError::Radius }));
}
