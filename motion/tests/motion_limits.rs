//! Sampled motion never exceeds the configured limits; schedules beyond
#![allow(clippy::field_reassign_with_default)]
//! them are refused with a typed error, never distorted.

use upm_motion::ActuatorCommand;
use upm_motion::{MotionError, MotionParams, PlateMotion, Rig, RigError, RigParams, ScheduleEntry};

fn corners(p: &MotionParams) -> [[f64; 2]; 4] {
    let [hx, hy] = p.plate_half_extent;
    [[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]]
}

#[test]
fn sampled_velocity_and_acceleration_within_limits() {
    let p = MotionParams::default();
    let l = p;
    let mut m = PlateMotion::new(p).expect("valid");
    let es: Vec<_> = [0.58, -0.39, 0.48, -0.095, 0.7, -0.7, 0.0]
        .iter()
        .enumerate()
        .map(|(i, &k)| ScheduleEntry {
            center: [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]][i % 4],
            k,
        })
        .collect();
    m.set_schedule(&es).expect("playable");
    // Fine sampling between ticks too (10 samples per tick).
    let h = p.tick();
    let mut peak = [0.0f64; 4];
    for i in 0..m.cycle_ticks() * 10 {
        let s = m.sample(i as f64 * h / 10.0);
        peak[0] = peak[0].max(s.pose.theta.abs());
        peak[1] = peak[1].max(s.velocity.theta.abs());
        peak[2] = peak[2].max(s.acceleration.theta.abs());
        for c in corners(&p) {
            let v = s.velocity.at(&s.pose, s.pose.to_world(c));
            peak[3] = peak[3].max(v[0].hypot(v[1]));
        }
    }
    assert!(peak[0] <= l.max_angle, "angle {}", peak[0]);
    assert!(peak[1] <= l.max_angular_velocity, "ω {}", peak[1]);
    assert!(peak[2] <= l.max_angular_acceleration, "α {}", peak[2]);
    assert!(peak[3] <= l.max_point_speed, "point speed {}", peak[3]);
    // And the velocity is continuous (no instantaneous reversal).
    for i in 1..m.cycle_ticks() * 10 {
        let a = m.sample((i - 1) as f64 * h / 10.0).velocity.theta;
        let b = m.sample(i as f64 * h / 10.0).velocity.theta;
        assert!((a - b).abs() <= l.max_angular_acceleration * h / 10.0 * 1.000001, "jump at {i}");
    }
}

#[test]
fn too_asymmetric_slot_is_refused_with_the_playable_bound() {
    let mut p = MotionParams::default();
    p.max_angular_acceleration = 10_000.0;
    let mut m = PlateMotion::new(p).expect("valid");
    let r = m.set_schedule(&[ScheduleEntry { center: [1.0, 0.5], k: 0.9 }]);
    match r {
        Err(MotionError::FastPhaseInfeasible { slot: 0, max_k, .. }) => {
            assert!(max_k > 0.0 && max_k < 0.9, "max_k {max_k}");
            // The reported bound is playable.
            assert!(m.set_schedule(&[ScheduleEntry { center: [1.0, 0.5], k: max_k * 0.999 }]).is_ok());
        }
        other => panic!("expected FastPhaseInfeasible, got {other:?}"),
    }
}

#[test]
fn refusal_keeps_previous_motion() {
    let mut m = PlateMotion::new(MotionParams::default()).expect("valid");
    m.set_schedule(&[ScheduleEntry { center: [1.0, 0.5], k: 0.3 }]).expect("playable");
    let before = m.sample_tick(7);
    assert!(m.set_schedule(&[ScheduleEntry { center: [1.0, 0.5], k: 0.999 }]).is_err());
    assert!(m.set_schedule(&[ScheduleEntry { center: [f64::NAN, 0.5], k: 0.1 }]).is_err());
    assert_eq!(m.sample_tick(7), before);
}

#[test]
fn invalid_params_are_refused() {
    let mut p = MotionParams::default();
    p.tick_hz = f64::NAN;
    assert!(PlateMotion::new(p).is_err());
    let mut p = MotionParams::default();
    p.k_max = 1.0;
    assert!(p.validate().is_err());
}

#[test]
fn rig_round_trip_and_limits() {
    let rig = Rig::new(RigParams::default()).expect("default rig");
    let pose = upm_motion::Pose { x: 1.2e-3, y: -0.7e-3, theta: 9e-4 };
    let mut s = [0.0; upm_motion::MAX_ACTUATORS];
    rig.actuator_positions(&pose, &mut s);
    let back = rig.pose_from_actuators(&s);
    assert!(
        (back.x - pose.x).abs() < 1e-12
            && (back.y - pose.y).abs() < 1e-12
            && (back.theta - pose.theta).abs() < 1e-12
    );
    let mut m = PlateMotion::new(MotionParams::default()).expect("valid");
    m.set_schedule(&[ScheduleEntry { center: [1.0, 0.5], k: 0.5 }]).expect("playable");
    assert!(rig.check_motion(&m).is_ok());
    let mut weak = RigParams::default();
    for a in &mut weak.actuators {
        a.max_force = 10.0;
    }
    let weak = Rig::new(weak).expect("valid");
    assert!(matches!(weak.check_motion(&m), Err(RigError::ForceLimit { .. })));
    let mut cmd = ActuatorCommand::default();
    rig.command(&m.sample_tick(0), &mut cmd);
    assert_eq!(cmd.position, [0.0; upm_motion::MAX_ACTUATORS], "home at a cycle start");
}

#[test]
fn singular_rig_is_refused() {
    let mut p = RigParams::default();
    for a in &mut p.actuators {
        a.direction = [1.0, 0.0];
    }
    assert!(matches!(Rig::new(p), Err(RigError::Singular)));
}
