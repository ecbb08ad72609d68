//! Any playable schedule is closed: home at every slot boundary, exactly.

use proptest::prelude::*;
use upm_motion::{MotionError, MotionParams, PlateMotion, ScheduleEntry};

fn entries() -> impl Strategy<Value = Vec<ScheduleEntry>> {
    prop::collection::vec(
        ((-3.0f64..3.0, -3.0f64..3.0), -0.95f64..0.95)
            .prop_map(|((x, y), k)| ScheduleEntry { center: [x, y], k }),
        1..12,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn home_at_every_slot_boundary(es in entries()) {
        let mut m = PlateMotion::new(MotionParams::default()).expect("defaults valid");
        match m.set_schedule(&es) {
            // Refusal is allowed (limits), distortion is not: check it names a slot.
            Err(e) => prop_assert!(!matches!(e, MotionError::Params(_)), "{e}"),
            Ok(()) => {
                let n = m.slot_ticks();
                for cycle in 0..2u64 {
                    for slot in 0..es.len() as u64 {
                        let s = m.sample_tick(cycle * m.cycle_ticks() + slot * n);
                        prop_assert!(s.pose.x.abs() <= 1e-12 && s.pose.y.abs() <= 1e-12 && s.pose.theta.abs() <= 1e-12,
                            "slot {} starts at {:?}", slot, s.pose);
                        prop_assert!(s.velocity.theta.abs() <= 1e-12);
                    }
                }
                // The angle swept forward equals the angle swept back.
                for sl in m.slots() {
                    let p = &sl.profile;
                    prop_assert!(p.theta[p.n - 1].abs() <= 1e-12 * sl.amplitude.max(1e-300) + 1e-18);
                    let peak = p.eval(sl.t_slow).theta;
                    prop_assert!((peak - sl.amplitude).abs() <= 1e-12 * sl.amplitude);
                }
            }
        }
    }

    #[test]
    fn slow_phase_fraction_is_k(es in entries()) {
        let mut m = PlateMotion::new(MotionParams::default()).expect("defaults valid");
        if m.set_schedule(&es).is_ok() {
            for sl in m.slots() {
                // The signed angular velocity is ≥ 0 before t_s and ≤ 0 after,
                // with sign(k) the slow direction: k = (t_s − t_f)/τ.
                let tau = m.params().slot_duration();
                prop_assert!(((2.0 * sl.t_slow - tau) / tau - sl.k.abs()).abs() < 1e-12);
                for i in 0..400 {
                    let t = tau * (i as f64 + 0.5) / 400.0;
                    let w = sl.profile.eval(t).omega;
                    if t < sl.t_slow { prop_assert!(w >= 0.0) } else { prop_assert!(w <= 0.0) }
                }
            }
        }
    }
}

#[test]
fn empty_schedule_holds_home() {
    let m = PlateMotion::new(MotionParams::default()).expect("defaults valid");
    assert_eq!(m.cycle_ticks(), 0);
    assert_eq!(m.sample_tick(12345).pose, upm_motion::Pose::HOME);
}

#[test]
fn time_and_tick_sampling_agree() {
    let mut m = PlateMotion::new(MotionParams::default()).expect("defaults valid");
    m.set_schedule(&[
        ScheduleEntry { center: [1.0, 0.5], k: 0.4 },
        ScheduleEntry { center: [-1.0, 0.5], k: -0.6 },
    ])
    .expect("playable");
    let h = m.params().tick();
    for tick in 0..m.cycle_ticks() * 2 {
        let a = m.sample_tick(tick);
        let b = m.sample(tick as f64 * h);
        assert!((a.pose.theta - b.pose.theta).abs() < 1e-12, "tick {tick}");
    }
}

/// Sampling is periodic in the cycle on both sides of the 32-bit fast path
/// (ticks past u32::MAX take the 64-bit division).
#[test]
fn sample_tick_is_periodic_past_32_bit_ticks() {
    let mut m = PlateMotion::new(MotionParams::default()).expect("defaults valid");
    let es = [ScheduleEntry { center: [0.3, -0.2], k: 0.4 }, ScheduleEntry { center: [-0.5, 0.1], k: -0.7 }];
    m.set_schedule(&es).expect("playable");
    let cycle = m.cycle_ticks();
    let far = (u32::MAX as u64 / cycle + 3) * cycle;
    assert!(far > u32::MAX as u64);
    for t in (0..cycle).step_by(7) {
        let (near, past) = (m.sample_tick(t), m.sample_tick(far + t));
        assert_eq!(near, past, "tick {t}");
        assert_eq!(near.cycle_start, t == 0);
    }
}
