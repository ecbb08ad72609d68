//! Fuzz: message validation. Any bytes a peer writes into shared memory, read as a payload, must
//! neither panic in validate() or the accessors nor pass validation while
//! breaking an invariant the core relies on.

use ipc_types::{
    ExplicitSchedule, ForceRequest, MAX_CURLS, PartStates, Schedule, Telemetry, ValidationLimits,
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

fn body() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(any::<u8>(), 1..8192)
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
            }
            prop_assert!(m.stamp_ns <= l.now_ns.saturating_add(l.max_future_skew_ns));
        } else {
            let _ = verdict.map_err(|e| e.to_string());
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
            let _ = parts.push(ipc_types::PartState::new(*id, 0, 0, [0.5, -0.5, 0.0], [0.0; 3]));
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
        if parts.validate(&l).is_ok() {
            for (i, p) in parts.parts().iter().enumerate() {
                prop_assert!(parts.parts()[..i].iter().all(|q| q.id != p.id));
                prop_assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0);
            }
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
