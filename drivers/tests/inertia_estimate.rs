//! The motor loop's plate inertia estimate against the simulator's drives:
//! a plate heavier than its model is found from the drives' effort, and an
//! exact plate is found exact however finely the drives step their servo.

use drivers::{ActuatorKind, PlateTruth, SimConfig, Simulator};
use upm_hardware::PlateState;
use upm_hardware::playback::play_estimating;
use upm_motion::{
    InertiaEstimate, InertiaParams, MotionParams, PlateFollow, PlateMotion, Rig, ScheduleEntry,
};

/// The scales after `cycles` cycles of a three-center schedule on a plate
/// `mass_error` heavier than the model, its drives updating `substeps`
/// times a tick, the estimate modelling them as `servo`.
fn learnt(mass_error: f64, substeps: u32, servo: PlateFollow, cycles: u64) -> [f64; 2] {
    let mut truth = PlateTruth::NOMINAL;
    truth.plate_mass_error = mass_error;
    let cfg = SimConfig { truth, substeps, ..SimConfig::default() };
    let mut sim = Simulator::new(cfg, &[]).expect("sim");
    let mut rig = Rig::new(cfg.rig).expect("rig");
    let mut m = PlateMotion::new(MotionParams::default()).expect("motion");
    let entries = [
        ScheduleEntry { center: [-1.0, 0.5], k: 0.6 },
        ScheduleEntry { center: [1.0, -0.5], k: -0.4 },
        ScheduleEntry { center: [0.3, 2.0], k: 0.3 },
    ];
    m.set_schedule(&entries).expect("playable");
    assert_eq!(cfg.actuator, ActuatorKind::SecondOrder, "a servo plate");
    let params = InertiaParams { servo, servo_substeps: substeps, ..InertiaParams::default() };
    let mut estimate = InertiaEstimate::new(params);
    let (n, mut state) = (m.cycle_ticks(), PlateState::default());
    for c in 0..cycles {
        play_estimating(&mut sim, &rig, &m, c * n, n, &mut state, Some(&mut estimate)).expect("read");
        rig.set_inertia_scale(estimate.end_cycle());
    }
    assert_eq!((estimate.updates(), estimate.skipped()), (cycles, 0));
    estimate.scale()
}

const DRIVES: PlateFollow = PlateFollow::Servo { bandwidth_hz: 1000.0, damping: 0.7 };

#[test]
fn a_plate_heavier_than_its_model_is_found_from_the_drives_effort() {
    for substeps in [1, 64] {
        let s = learnt(0.10, substeps, DRIVES, 40);
        assert!((s[0] - 1.10).abs() < 2e-3 && (s[1] - 1.10).abs() < 1e-2, "{substeps}: {s:?}");
        let s = learnt(-0.08, substeps, DRIVES, 40);
        assert!((s[0] - 0.92).abs() < 2e-3 && (s[1] - 0.92).abs() < 1e-2, "{substeps}: {s:?}");
    }
}

#[test]
fn an_exact_plate_is_found_exact_because_the_drives_own_effort_is_modelled() {
    let s = learnt(0.0, 64, DRIVES, 30);
    assert!(s.iter().all(|x| (x - 1.0).abs() < 2e-3), "{s:?}");
    // Taken as exact, a finely stepped servo's push through each tick
    // (its reference is linear, the feed-forward the tick's mean) reads as
    // a heavier plate: the check above would fail without the model.
    let s = learnt(0.0, 64, PlateFollow::Exact, 30);
    assert!(s[0] > 1.005, "{s:?}");
}
