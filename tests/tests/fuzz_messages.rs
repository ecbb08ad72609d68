//! Fuzz: message validation. Any bytes a peer writes into shared memory, read as a payload, must
//! neither panic in validate() or the accessors nor pass validation while
//! breaking an invariant the core relies on.

use ipc_types::{
    ExplicitSchedule, FEED_RECENT_PICKS, FeedStatus, ForceRequest, LineStatus, MAX_CURLS, MAX_PICK_POSES,
    MAX_SHAPE_VERTICES, PROTOCOL_VERSION, PartState, PartStates, PartStatesError, PickCommand,
    PickCommandError, PickEvent, PickPoseState, RECIPE_PATH_BYTES, RecipeCommand, RecipeCommandError,
    RejectReason, SHAPE_DISC, SHAPE_POINT, SHAPE_POLYGON, Schedule, ShapeError, Telemetry, ValidationLimits,
};
use proptest::prelude::*;
use upm_tests::{from_bytes, patch_header};

fn limits_strategy() -> impl Strategy<Value = ValidationLimits> {
    (
        any::<[f64; 2]>(),
        0.0..2.0f64,
        any::<u64>(),
        any::<u64>(),
        any::<u32>(),
        any::<f64>(),
        any::<[u32; 2]>(),
    )
        .prop_map(|(half, sane_half, now, skew, centers, k_max, classes)| {
            let mut l = ValidationLimits::new(if half[0].is_nan() { [sane_half; 2] } else { half }, now);
            l.max_future_skew_ns = skew;
            l.center_count = centers;
            l.k_max = k_max;
            l.part_class_count = classes[0];
            l.friction_class_count = classes[1];
            l
        })
}

/// An accepted outline, checked by other means than `check_shape`: a disc
/// of finite radius in (0, extent]; a polygon of 3..=8 finite vertices
/// within `extent` of the position, with non-zero area and every vertex on
/// the inner side of every edge (convex and simple).
fn outline_is_sound(p: &PartState, extent: f64) -> bool {
    match p.shape {
        SHAPE_POINT => true,
        SHAPE_DISC => p.radius.is_finite() && p.radius > 0.0 && p.radius <= extent,
        SHAPE_POLYGON => {
            let n = p.vertex_count as usize;
            if !(3..=MAX_SHAPE_VERTICES).contains(&n) {
                return false;
            }
            let v = &p.vertices[..n];
            if !v
                .iter()
                .all(|q| q[0].is_finite() && q[1].is_finite() && q[0].hypot(q[1]) <= extent * (1.0 + 1e-12))
            {
                return false;
            }
            let area2: f64 = (0..n).map(|i| v[i][0] * v[(i + 1) % n][1] - v[(i + 1) % n][0] * v[i][1]).sum();
            if area2 == 0.0 || !area2.is_finite() {
                return false;
            }
            (0..n).all(|i| {
                let (a, b) = (v[i], v[(i + 1) % n]);
                let e = [b[0] - a[0], b[1] - a[1]];
                v.iter().all(|c| {
                    let d = [c[0] - a[0], c[1] - a[1]];
                    let cross = e[0] * d[1] - e[1] * d[0];
                    area2.signum() * cross >= -1e-9 * e[0].hypot(e[1]) * d[0].hypot(d[1])
                })
            })
        }
        _ => false,
    }
}

/// A refused outline is counted as `bad_shape` and its line names the
/// field; nothing else is counted as `bad_shape`.
fn shape_error_is_named(e: &PartStatesError) -> bool {
    let line = e.to_string();
    match e {
        PartStatesError::Shape { index, error } => {
            e.reason() == RejectReason::BadShape
                && line.starts_with(&format!("part_states.parts[{index}].{}: ", error.field()))
        }
        _ => e.reason() != RejectReason::BadShape && line.starts_with("part_states."),
    }
}

/// Up to a whole `PartStates` (the largest inbound payload, 13336 bytes);
/// a shorter body is repeated.
fn body() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(any::<u8>(), 1..=size_of::<PartStates>())
}

proptest! {
    #![proptest_config(upm_tests::fuzz_config(4096, 1))]

    #[test]
    fn part_states_never_panic(mut bytes in body(), count in 0u32..80, patch in any::<bool>(), l in limits_strategy()) {
        bytes.resize(bytes.len().max(8), 0);
        if patch { patch_header(&mut bytes, count); }
        let mut m: PartStates = from_bytes(&bytes);
        let verdict = m.validate(&l);
        prop_assert!(m.parts().len() <= PartStates::CAPACITY && m.parts_mut().len() <= PartStates::CAPACITY);
        if verdict.is_ok() {
            prop_assert!(m.count as usize <= PartStates::CAPACITY);
            for (i, p) in m.parts().iter().enumerate() {
                prop_assert!([p.x, p.y, p.theta, p.vx, p.vy, p.omega].iter().all(|v| v.is_finite()));
                prop_assert!(p.x.abs() <= l.plate_half_extent_m[0] && p.y.abs() <= l.plate_half_extent_m[1]);
                prop_assert!(m.parts()[..i].iter().all(|q| q.id != p.id));
                prop_assert!(outline_is_sound(p, l.max_part_extent()), "{p:?}");
            }
            prop_assert!(m.stamp_ns <= l.now_ns.saturating_add(l.max_future_skew_ns));
        } else if let Err(e) = verdict {
            prop_assert!(shape_error_is_named(&e), "{e}");
        }
        let _ = m.push(ipc_types::PartState::ZERO);
    }

    #[test]
    fn force_request_never_panics(mut bytes in body(), count in 0u32..80, patch in any::<bool>(), l in limits_strategy()) {
        bytes.resize(bytes.len().max(8), 0);
        if patch { patch_header(&mut bytes, count); }
        let mut m: ForceRequest = from_bytes(&bytes);
        let verdict = m.validate(&l);
        prop_assert!(m.entries().len() <= ForceRequest::CAPACITY && m.entries_mut().len() <= ForceRequest::CAPACITY);
        if verdict.is_ok() {
            prop_assert!(m.curl_count() <= MAX_CURLS);
            prop_assert!(m.deadline_ns >= m.stamp_ns);
            for e in m.entries() {
                prop_assert!(e.force_flag <= 1 && e.curl_flag <= 1 && (e.force_flag | e.curl_flag) == 1);
                prop_assert!(e.fx.is_finite() && e.fy.is_finite() && e.curl.is_finite());
            }
        } else {
            let _ = verdict.map_err(|e| e.to_string());
        }
        let _ = m.push(ipc_types::ForceEntry::curl(1, 0.0));
    }

    #[test]
    fn explicit_schedule_never_panics(mut bytes in body(), count in 0u32..200, patch in any::<bool>(), l in limits_strategy()) {
        bytes.resize(bytes.len().max(8), 0);
        if patch { patch_header(&mut bytes, count); }
        let m: ExplicitSchedule = from_bytes(&bytes);
        let verdict = m.validate(&l);
        prop_assert!(m.slots().len() <= ExplicitSchedule::CAPACITY);
        if verdict.is_ok() {
            prop_assert!(!m.slots().is_empty());
            for s in m.slots() {
                prop_assert!(s.center_index < l.center_count && s.k.abs() <= 1.0 && s.k.abs() <= l.k_max);
            }
        } else {
            let _ = verdict.map_err(|e| e.to_string());
        }
    }

    #[test]
    fn schedule_never_panics(mut bytes in body(), count in 0u32..200, patch in any::<bool>(), l in limits_strategy()) {
        bytes.resize(bytes.len().max(8), 0);
        if patch { patch_header(&mut bytes, count); }
        let m: Schedule = from_bytes(&bytes);
        let verdict = m.validate(&l);
        prop_assert!(m.slots().len() <= Schedule::CAPACITY);
        if verdict.is_ok() {
            prop_assert!(m.residual.is_finite() && m.residual >= 0.0 && m.condition >= 0.0 && m.saturated <= 1);
            for s in m.slots() {
                prop_assert!(s.x.is_finite() && s.y.is_finite() && s.k.abs() <= 1.0);
            }
        } else {
            let _ = verdict.map_err(|e| e.to_string());
        }
    }

    #[test]
    fn telemetry_never_panics(mut bytes in body(), state in 0u32..6, patch in any::<bool>(), l in limits_strategy()) {
        bytes.resize(bytes.len().max(8), 0);
        // Telemetry's second word is the state code, not a count.
        if patch { patch_header(&mut bytes, state); }
        let m: Telemetry = from_bytes(&bytes);
        let verdict = m.validate(&l);
        if verdict.is_ok() {
            prop_assert!(m.core_state().is_some());
            prop_assert!(m.parts_age_ms >= 0.0 && m.request_age_ms.is_finite());
            prop_assert!(m.latency.solver.is_ordered() && m.latency.motor_wakeup.p50_ns <= m.latency.motor_wakeup.max_ns);
        } else {
            let _ = verdict.map_err(|e| e.to_string());
        }
    }

    #[test]
    fn feed_status_never_panics(
        mut bytes in body(),
        counts in (0u32..20, 0u32..20),
        patch in any::<bool>(),
        l in limits_strategy(),
    ) {
        // Past the header, `recent_count` too, so the picks are walked.
        let at = core::mem::offset_of!(FeedStatus, recent_count);
        bytes.resize(bytes.len().max(at + 4), 0);
        if patch {
            patch_header(&mut bytes, counts.0);
            bytes[at..at + 4].copy_from_slice(&counts.1.to_ne_bytes());
        }
        let mut m: FeedStatus = from_bytes(&bytes);
        let verdict = m.validate(&l);
        prop_assert!(m.poses().len() <= MAX_PICK_POSES && m.poses_mut().len() <= MAX_PICK_POSES);
        prop_assert!(m.recent().len() <= FEED_RECENT_PICKS);
        if verdict.is_ok() {
            prop_assert!(m.count as usize <= MAX_PICK_POSES && m.recent_count as usize <= FEED_RECENT_PICKS);
            prop_assert!([m.time_s, m.robot_busy_s, m.stuck_after_s].iter().all(|v| v.is_finite()));
            for p in m.recent() {
                let floats = [p.time_s, p.position_error_m, p.angle_error_rad, p.on_plate_s];
                prop_assert!(floats.iter().all(|v| v.is_finite()));
            }
            for p in m.poses() {
                prop_assert!(p.x.is_finite() && p.y.is_finite() && p.theta.is_finite());
            }
            prop_assert!(m.stamp_ns <= l.now_ns.saturating_add(l.max_future_skew_ns));
        } else if let Err(e) = verdict {
            prop_assert!(e.to_string().starts_with("feed_status."), "{}", e);
        }
        let _ = m.push(PickPoseState::ZERO);
        m.push_pick(PickEvent { number: u64::MAX, ..PickEvent::ZERO });
        prop_assert!(m.recent().last().is_some_and(|p| p.number == u64::MAX));
    }

    #[test]
    fn pick_command_never_panics(
        mut bytes in body(),
        pose in 0u32..20,
        part_id in 0u32..3,
        age in any::<u64>(),
        patch in any::<bool>(),
        mut l in limits_strategy(),
        max_age in prop::option::of(any::<u64>()),
    ) {
        // The whole message is 32 bytes; patched: a valid version, a pose
        // near the capacity, a stamp at or before now and a part id near
        // 0, so every check is reached.
        bytes.resize(bytes.len().max(size_of::<PickCommand>()), 0);
        if patch {
            patch_header(&mut bytes, pose);
            let at = core::mem::offset_of!(PickCommand, stamp_ns);
            bytes[at..at + 8].copy_from_slice(&l.now_ns.saturating_sub(age % 1_000_000_000).to_ne_bytes());
            let at = core::mem::offset_of!(PickCommand, part_id);
            bytes[at..at + 4].copy_from_slice(&part_id.to_ne_bytes());
        }
        if let Some(max_age) = max_age {
            l.max_age_ns = max_age;
        }
        let m: PickCommand = from_bytes(&bytes);
        let verdict = m.validate(&l);
        // Accepted exactly when every rule holds, checked by other means.
        let sound = m.protocol_version == PROTOCOL_VERSION
            && m.stamp_ns <= l.now_ns.saturating_add(l.max_future_skew_ns)
            && l.now_ns.saturating_sub(m.stamp_ns) <= l.max_age_ns
            && (m.pose as usize) < MAX_PICK_POSES
            && m.part_id != 0;
        prop_assert_eq!(verdict.is_ok(), sound, "{:?}: {:?}", m, verdict);
        if let Err(e) = verdict {
            prop_assert!(e.to_string().starts_with("pick_command."), "{}", e);
            let expected = match e {
                PickCommandError::Header(h) => h.reason(),
                PickCommandError::PoseOutOfRange { pose } => {
                    prop_assert_eq!(pose, m.pose);
                    RejectReason::CountExceedsCapacity
                }
                PickCommandError::NoPart => RejectReason::UnknownPart,
            };
            prop_assert_eq!(e.reason(), expected);
            let no_count = !matches!(e, PickCommandError::Header(ipc_types::HeaderError::CountExceedsCapacity { .. }));
            prop_assert!(no_count, "a pick has no count: {}", e);
        }
    }

    #[test]
    fn recipe_command_never_panics(
        mut bytes in body(),
        path_len in 0u32..260,
        age in any::<u64>(),
        patch in any::<bool>(),
        slash in any::<bool>(),
        ascii in any::<bool>(),
        mut l in limits_strategy(),
        max_age in prop::option::of(any::<u64>()),
    ) {
        // The whole message is 264 bytes; patched: a valid version, a
        // length near the capacity, a stamp at or before now, and a path
        // that may start with '/' and may be ASCII, so every check is reached.
        bytes.resize(bytes.len().max(size_of::<RecipeCommand>()), 0);
        if patch {
            patch_header(&mut bytes, path_len);
            let at = core::mem::offset_of!(RecipeCommand, stamp_ns);
            bytes[at..at + 8].copy_from_slice(&l.now_ns.saturating_sub(age % 1_000_000_000).to_ne_bytes());
            let at = core::mem::offset_of!(RecipeCommand, path);
            let path = &mut bytes[at..at + RECIPE_PATH_BYTES];
            if ascii {
                path.iter_mut().for_each(|b| *b &= 0x7F);
            }
            if slash {
                path[0] = b'/';
            }
        }
        if let Some(max_age) = max_age {
            l.max_age_ns = max_age;
        }
        let m: RecipeCommand = from_bytes(&bytes);
        let verdict = m.validate(&l);
        // Accepted exactly when every rule holds, checked by other means.
        let used = m.path.get(..m.path_len as usize);
        let text = used.and_then(|u| String::from_utf8(u.to_vec()).ok());
        let sound = m.protocol_version == PROTOCOL_VERSION
            && m.stamp_ns <= l.now_ns.saturating_add(l.max_future_skew_ns)
            && l.now_ns.saturating_sub(m.stamp_ns) <= l.max_age_ns
            && text.as_deref().is_some_and(|t| t.starts_with('/'));
        prop_assert_eq!(verdict.is_ok(), sound, "{:?}: {:?}", m, verdict);
        // path() reads what validate() read, whatever the header says.
        prop_assert_eq!(m.path().ok(), text.as_deref());
        if verdict.is_ok() {
            // What the receiver opens: within the capacity, absolute, and
            // new() rebuilds the same used bytes.
            let path = m.path().unwrap_or_default();
            let again = RecipeCommand::new(path, m.seq, m.stamp_ns);
            prop_assert_eq!(again.map(|a| a.path[..a.path_len as usize].to_vec()), Ok(path.as_bytes().to_vec()));
        }
        if let Err(e) = verdict {
            prop_assert!(e.to_string().starts_with("recipe_command."), "{}", e);
            let expected = match e {
                RecipeCommandError::Header(h) => h.reason(),
                RecipeCommandError::PathTooLong { len } => {
                    prop_assert_eq!(len, m.path_len);
                    prop_assert!(len as usize > RECIPE_PATH_BYTES);
                    RejectReason::CountExceedsCapacity
                }
                RecipeCommandError::NotUtf8 | RecipeCommandError::NotAbsolute => RejectReason::BadPath,
            };
            prop_assert_eq!(e.reason(), expected);
            let no_count = !matches!(e, RecipeCommandError::Header(ipc_types::HeaderError::CountExceedsCapacity { .. }));
            prop_assert!(no_count, "a recipe's header has no count: {}", e);
        }
    }

    #[test]
    fn line_status_never_panics(mut bytes in body(), patch in any::<bool>(), l in limits_strategy()) {
        bytes.resize(bytes.len().max(size_of::<LineStatus>()), 0);
        if patch {
            patch_header(&mut bytes, 0);
            let at = core::mem::offset_of!(LineStatus, stamp_ns);
            bytes[at..at + 8].copy_from_slice(&l.now_ns.to_ne_bytes());
        }
        let m: LineStatus = from_bytes(&bytes);
        let verdict = m.validate(&l);
        // Any age, any counter: only the version and a stamp from the future refuse it.
        let sound = m.protocol_version == PROTOCOL_VERSION
            && m.stamp_ns <= l.now_ns.saturating_add(l.max_future_skew_ns);
        prop_assert_eq!(verdict.is_ok(), sound, "{:?}: {:?}", m, verdict);
        if let Err(e) = verdict {
            prop_assert!(e.to_string().starts_with("line_status."), "{}", e);
        }
        let sum: u128 = m.refusals().iter().map(|(_, n)| u128::from(*n)).sum();
        prop_assert_eq!(u128::from(m.total_refusals()), sum.min(u128::from(u64::MAX)));
    }
}

const SQUARE: [[f64; 2]; 4] = [[0.01, 0.01], [-0.01, 0.01], [-0.01, -0.01], [0.01, -0.01]];

/// Floats a hostile outline may carry.
fn wild_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -0.5..0.5f64,
        2 => any::<f64>(),
        1 => prop::sample::select(vec![
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            1e-300,
            1e300,
            f64::MAX,
            -f64::MAX,
        ]),
    ]
}

/// `k` vertices on a circle of `radius` about `centre`, at angles spaced by
/// the normalised `gaps` (each ≥ 0.08 rad): convex and simple by
/// construction, in either winding.
fn on_a_circle(
    k: usize,
    radius: f64,
    gaps: &[f64],
    turn: f64,
    clockwise: bool,
    centre: [f64; 2],
) -> Vec<[f64; 2]> {
    let total: f64 = gaps[..k].iter().sum();
    let mut angle = turn;
    let mut v: Vec<[f64; 2]> = gaps[..k]
        .iter()
        .map(|g| {
            angle += core::f64::consts::TAU * g / total;
            [centre[0] + radius * angle.cos(), centre[1] + radius * angle.sin()]
        })
        .collect();
    if clockwise {
        v.reverse();
    }
    v
}

/// What `check_shape` must answer, worked out field by field; `None` when
/// only convexity decides (then an accepted outline must be sound).
fn expected_outline(p: &PartState, extent: f64) -> Option<Result<(), ShapeError>> {
    let extent = extent.min(ipc_types::MAX_OUTLINE_M);
    match p.shape {
        SHAPE_POINT => Some(Ok(())),
        SHAPE_DISC if !(p.radius.is_finite() && p.radius >= ipc_types::MIN_OUTLINE_M) => {
            Some(Err(ShapeError::Radius))
        }
        SHAPE_DISC if p.radius > extent => Some(Err(ShapeError::RadiusTooLarge)),
        SHAPE_DISC => Some(Ok(())),
        SHAPE_POLYGON => {
            let n = p.vertex_count as usize;
            if !(3..=MAX_SHAPE_VERTICES).contains(&n) {
                return Some(Err(ShapeError::VertexCount));
            }
            let v = &p.vertices[..n];
            if v.iter().any(|q| !(q[0].is_finite() && q[1].is_finite())) {
                return Some(Err(ShapeError::NonFinite));
            }
            let far = v.iter().map(|q| q[0].hypot(q[1])).fold(0.0, f64::max);
            if (far - extent).abs() <= 1e-12 * extent {
                None // on the bound: rounding decides
            } else if far > extent {
                Some(Err(ShapeError::VertexTooFar))
            } else {
                None
            }
        }
        _ => Some(Err(ShapeError::Code)),
    }
}

/// Bytes of a payload, to corrupt a valid message in place.
fn to_bytes<T: Copy>(value: &T) -> Vec<u8> {
    // SAFETY: payloads have no padding, so all size_of::<T>() bytes are initialised.
    unsafe { core::slice::from_raw_parts((value as *const T).cast::<u8>(), size_of::<T>()) }.to_vec()
}

proptest! {
    #![proptest_config(upm_tests::fuzz_config(4096, 1))]

    /// A valid message with a few corrupted bytes: reaches the deep checks
    /// (duplicates, curls, flags) that random bodies rarely get to.
    #[test]
    fn corrupted_valid_messages_never_panic(
        n in 0usize..=64,
        ids in prop::collection::vec(0u32..40, 64),
        corruptions in prop::collection::vec((any::<usize>(), any::<u8>()), 1..4),
    ) {
        let l = ValidationLimits::new([1.0, 1.0], 1_000);
        let mut parts = PartStates::new();
        let mut request = ForceRequest::new();
        request.deadline_ns = 10;
        for (i, id) in ids.iter().take(n).enumerate() {
            let point = PartState::new(*id, 0, 0, [0.5, -0.5, 0.0], [0.0; 3]);
            let part = match i % 3 {
                0 => point,
                1 => point.with_disc(0.02),
                _ => point.with_polygon(&SQUARE).unwrap_or(point),
            };
            let _ = parts.push(part);
            let entry = if i % 3 == 0 {
                ipc_types::ForceEntry::force_and_curl(*id, [0.1, 0.0], 0.2)
            } else {
                ipc_types::ForceEntry::force(*id, [0.1, 0.0])
            };
            let _ = request.push(entry);
        }
        let mut pb = to_bytes(&parts);
        let mut rb = to_bytes(&request);
        for (at, value) in &corruptions {
            let pl = pb.len();
            pb[at % pl] = *value;
            let rl = rb.len();
            rb[at % rl] = *value;
        }
        let parts: PartStates = from_bytes(&pb);
        match parts.validate(&l) {
            Ok(()) => {
                for (i, p) in parts.parts().iter().enumerate() {
                    prop_assert!(parts.parts()[..i].iter().all(|q| q.id != p.id));
                    prop_assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0);
                    prop_assert!(outline_is_sound(p, 1.0), "{p:?}");
                }
            }
            Err(e) => prop_assert!(shape_error_is_named(&e), "{e}"),
        }
        let request: ForceRequest = from_bytes(&rb);
        if request.validate(&l).is_ok() {
            prop_assert!(request.curl_count() <= MAX_CURLS);
            for (i, e) in request.entries().iter().enumerate() {
                prop_assert!(request.entries()[..i].iter().all(|q| q.part_id != e.part_id));
                prop_assert!(e.force_flag <= 1 && e.curl_flag <= 1);
            }
        }
    }
}

proptest! {
    #![proptest_config(upm_tests::fuzz_config(4096, 1))]

    /// A part on the plate with any outline fields a hostile sender can
    /// write: never a panic; refused exactly when a field is bad, as
    /// `bad_shape` naming it; an outline on a circle within the plate
    /// passes; whatever passes is sound.
    #[test]
    fn hostile_outlines_are_refused_as_bad_shape_and_sound_ones_pass(
        shape in prop_oneof![4 => 0u32..3, 1 => any::<u32>()],
        radius in wild_f64(),
        vertex_count in prop_oneof![4 => 0u32..=10, 1 => any::<u32>()],
        raw in prop::array::uniform8(prop::array::uniform2(wild_f64())),
        circle in (3usize..=MAX_SHAPE_VERTICES, 1e-3..0.2f64, prop::collection::vec(1.0..10.0f64, 8)),
        turn in 0.0..core::f64::consts::TAU,
        clockwise in any::<bool>(),
        centre in prop::array::uniform2(-0.1..0.1f64),
        use_circle in any::<bool>(),
        extent in prop_oneof![4 => 0.01..1.0f64, 1 => Just(f64::INFINITY)],
        index in 0usize..4,
        theta in wild_f64(),
    ) {
        let l = ValidationLimits::new([extent, extent / 2.0], 1_000);
        let mut m = PartStates::new();
        m.stamp_ns = 1_000;
        for id in 0..4 {
            m.push(PartState::new(id, 0, 0, [0.0, 0.0, 0.0], [0.0; 3])).expect("fits");
        }
        let p = &mut m.parts_mut()[index];
        (p.shape, p.radius, p.vertex_count, p.vertices) = (shape, radius, vertex_count, raw);
        // theta does not change the verdict (it turns the outline only
        // once the core reads it; checked below).
        if theta.is_finite() { p.theta = theta; }
        let (k, r, gaps) = circle;
        let mut sound_circle = false;
        if use_circle {
            let v = on_a_circle(k, r, &gaps, turn, clockwise, centre);
            p.shape = SHAPE_POLYGON;
            p.vertex_count = k as u32;
            p.vertices[..k].copy_from_slice(&v);
            let area = 0.5 * (0..k).map(|i| v[i][0] * v[(i + 1) % k][1] - v[(i + 1) % k][0] * v[i][1]).sum::<f64>().abs();
            let min_area = ipc_types::MIN_OUTLINE_M * ipc_types::MIN_OUTLINE_M;
            sound_circle = r + centre[0].hypot(centre[1]) < extent * (1.0 - 1e-9) && area > 1.01 * min_area;
        }
        let part = *p;
        let verdict = m.validate(&l);
        let got = match verdict {
            Ok(()) => Ok(()),
            Err(PartStatesError::Shape { index: i, error }) => {
                prop_assert_eq!(i, index);
                Err(error)
            }
            Err(e) => return Err(TestCaseError::fail(format!("not an outline error: {e}"))),
        };
        if let Err(e) = verdict {
            prop_assert!(shape_error_is_named(&e), "{}", e);
        }
        match expected_outline(&part, extent) {
            Some(want) => prop_assert_eq!(got, want, "{:?}", part),
            None => prop_assert!(
                matches!(got, Ok(()) | Err(ShapeError::NotConvex | ShapeError::TooSmall | ShapeError::VertexTooFar)),
                "{:?}: {:?}", part, got
            ),
        }
        if sound_circle {
            prop_assert_eq!(got, Ok(()), "a convex polygon within the plate was refused: {:?}", part);
        }
        if got.is_ok() {
            prop_assert!(outline_is_sound(&part, extent), "{:?}", part);
            // Accepted means solvable: turned by any theta into plate axes,
            // the outline still passes the solver's own check.
            let turned = upm_solver::PartShape::from_wire(&part);
            prop_assert_eq!(turned.check(), Ok(()), "{:?} turned by {}", part, part.theta);
        }
    }
}

/// Random bytes must reach the outline check too (an unknown `shape` code
/// is all but certain once a part's pose passes).
#[test]
fn patched_random_bodies_reach_the_outline_check() {
    let l = ValidationLimits::new([1.0, 1.0], u64::MAX);
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut shape_errors = 0;
    for _ in 0..256 {
        let mut bytes: Vec<u8> = (0..size_of::<PartStates>())
            .map(|_| {
                // xorshift64: reproducible, no dependency.
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state as u8
            })
            .collect();
        patch_header(&mut bytes, 1);
        let m: PartStates = from_bytes(&bytes);
        if let Err(e @ PartStatesError::Shape { .. }) = m.validate(&l) {
            assert!(shape_error_is_named(&e), "{e}");
            shape_errors += 1;
        }
    }
    assert!(shape_errors > 0, "random bodies never reached the outline check");
}

/// The patched path must really reach the per-entry checks, otherwise the
/// properties above would only ever exercise the header checks.
#[test]
fn patched_random_bodies_reach_entry_checks() {
    let l = ValidationLimits::new([1.0, 1.0], u64::MAX);
    let mut entry_errors = 0;
    for seed in 0u8..64 {
        let mut bytes: Vec<u8> =
            (0..4096u32).map(|i| (i as u8).wrapping_mul(31).wrapping_add(seed)).collect();
        patch_header(&mut bytes, 5);
        let m: PartStates = from_bytes(&bytes);
        if matches!(
            m.validate(&l),
            Err(ipc_types::PartStatesError::NonFinite { .. } | ipc_types::PartStatesError::OffPlate { .. })
        ) {
            entry_errors += 1;
        }
    }
    assert!(entry_errors > 0, "random bodies never reached the per-part checks");
}
