//! The hidden truth: a worn plate moves its parts as the first-order model
//! of its errors says, not as the controller's model does; friction scales
//! by part and by place; the sensors report what they read.

use drivers::{ActuatorKind, BodyShape, FrictionMap, PartSpec, PartState, PlateTruth, SimConfig, Simulator};
use upm_hardware::playback::play;
use upm_hardware::{ActuatorCommand, MAX_ACTUATORS, PlateDriver, PlateState};
use upm_motion::{MotionParams, PlateMotion, Pose, Rig, ScheduleEntry, Twist};

const CENTER: [f64; 2] = [0.5, 0.2];

fn point(p: [f64; 2]) -> PartSpec {
    PartSpec { shape: BodyShape::Point { radius: 0.01 }, mass: 0.04, position: p, angle: 0.0 }
}

/// Mean force per unit mass on parts restarted at rest at `at` each
/// cycle, over `cycles` cycles of one slot about `CENTER` (k = 0.6).
fn measured(cfg: SimConfig, at: &[[f64; 2]], friction: &[f64], cycles: u64) -> Vec<[f64; 2]> {
    measured_on(cfg, Rig::new(cfg.rig).expect("rig"), at, friction, cycles)
}

/// [`measured`], commanded through `rig`.
fn measured_on(cfg: SimConfig, rig: Rig, at: &[[f64; 2]], friction: &[f64], cycles: u64) -> Vec<[f64; 2]> {
    let mut motion = PlateMotion::new(MotionParams::default()).expect("motion");
    motion.set_schedule(&[ScheduleEntry { center: CENTER, k: 0.6 }]).expect("schedule");
    let specs: Vec<PartSpec> = at.iter().map(|&p| point(p)).collect();
    // Parts meet nothing: two may share a place.
    let mut sim = Simulator::new(SimConfig { collisions: false, ..cfg }, &specs).expect("sim");
    for (i, &s) in friction.iter().enumerate() {
        assert!(sim.set_part_friction(i, s));
    }
    let (n, t) = (motion.cycle_ticks(), motion.cycle_duration());
    let mut sum = vec![[0.0; 2]; at.len()];
    let mut state = PlateState::default();
    for c in 0..cycles {
        for (i, &p) in at.iter().enumerate() {
            assert!(sim.set_part(i, PartState { position: p, ..PartState::default() }));
        }
        play(&mut sim, &rig, &motion, c * n, n, &mut state).expect("play");
        for (i, s) in sum.iter_mut().enumerate() {
            let v = sim.part(i).expect("part").velocity;
            *s = [s[0] + v[0] / t / cycles as f64, s[1] + v[1] / t / cycles as f64];
        }
    }
    sim.parts();
    sum
}

fn angle(f: [f64; 2]) -> f64 {
    f[1].atan2(f[0])
}

/// The twist a commanded twist becomes, to first order.
fn true_twist(truth: &PlateTruth, xi: Twist) -> Twist {
    truth.true_twist(&upm_motion::RigParams::default(), xi).expect("rig")
}

/// The center a commanded rotation about `c` really turns about.
fn effective_center(truth: &PlateTruth, c: [f64; 2]) -> [f64; 2] {
    let t = true_twist(truth, Twist { x: c[1], y: -c[0], theta: 1.0 });
    [-t.y / t.theta, t.x / t.theta]
}

/// The inverse of the map commanded twist → true twist.
fn exact_correction(truth: &PlateTruth) -> [[f64; 3]; 3] {
    let m = truth.twist_map(&upm_motion::RigParams::default()).expect("rig");
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    core::array::from_fn(|r| {
        core::array::from_fn(|c| {
            let (r1, r2, c1, c2) = ((c + 1) % 3, (c + 2) % 3, (r + 1) % 3, (r + 2) % 3);
            (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det
        })
    })
}

#[test]
fn the_exact_correction_makes_a_worn_plate_turn_about_the_commanded_center() {
    let at = [[-0.6, 0.3], [-0.4, -0.35], [0.1, 0.4], [0.8, -0.3]];
    let worn = SimConfig {
        truth: PlateTruth { friction_map: FrictionMap::FLAT, ..PlateTruth::worn() },
        ..SimConfig::default()
    };
    let corrected = Rig::new(worn.rig).expect("rig").with_correction(exact_correction(&worn.truth));
    let f = measured_on(worn, corrected, &at, &[], 6);
    let f_nom = measured(SimConfig::default(), &at, &[], 6);
    let c_eff = effective_center(&worn.truth, CENTER);
    for (i, p) in at.iter().enumerate() {
        let dir = |c: [f64; 2]| angle([-(p[1] - c[1]), p[0] - c[0]]);
        let (e, e_nom) = (angle(f[i]) - dir(CENTER), angle(f_nom[i]) - dir(CENTER));
        let uncorrected = (dir(c_eff) - dir(CENTER)).abs();
        // As close to the wanted direction as the nominal plate gets, and
        // far closer than the uncorrected worn plate.
        assert!(
            (e - e_nom).abs() < 0.2 * uncorrected,
            "part {i}: {e} against {e_nom}, uncorrected {uncorrected}"
        );
    }
}

#[test]
fn a_worn_plate_turns_about_the_center_its_errors_predict() {
    let at = [[-0.6, 0.3], [-0.4, -0.35], [0.1, 0.4], [0.8, -0.3]];
    let nominal = SimConfig::default();
    let worn =
        SimConfig { truth: PlateTruth { friction_map: FrictionMap::FLAT, ..PlateTruth::worn() }, ..nominal };
    let f_nom = measured(nominal, &at, &[], 6);
    let f_worn = measured(worn, &at, &[], 6);
    let c_eff = effective_center(&worn.truth, CENTER);
    let shift = (c_eff[0] - CENTER[0]).hypot(c_eff[1] - CENTER[1]);
    assert!(shift > 5e-3, "the worn rig's errors must move the center: {shift}");
    for (i, p) in at.iter().enumerate() {
        let dir = |c: [f64; 2]| angle([-(p[1] - c[1]), p[0] - c[0]]);
        // The nominal plate pushes along R90(P − C), the worn one along
        // R90(P − C'), each within 0.2° (stick-slip and the servo's lag).
        let (e_nom, e_worn) = (angle(f_nom[i]) - dir(CENTER), angle(f_worn[i]) - dir(c_eff));
        let turned = (dir(c_eff) - dir(CENTER)).abs();
        assert!(e_nom.abs() < 3.5e-3 && e_worn.abs() < 3.5e-3, "part {i}: {e_nom} {e_worn}");
        assert!(turned > 2.0 * (e_nom.abs() + e_worn.abs()), "part {i}: turn {turned} not measurable");
    }
}

#[test]
fn friction_scales_with_the_part_and_with_the_map() {
    let at = [[-0.6, 0.3], [-0.6, 0.3], [0.1, -0.4]];
    let base = measured(SimConfig::default(), &at, &[], 4);
    let scaled = measured(SimConfig::default(), &at, &[1.0, 0.7, 1.0], 4);
    let norm = |f: [f64; 2]| f[0].hypot(f[1]);
    assert_eq!(base[0], scaled[0], "an unscaled part is untouched");
    let r = norm(scaled[1]) / norm(base[1]);
    assert!((r - 0.7).abs() < 0.02, "a part of 0.7 μ feels {r} of the force");
    let map = FrictionMap { coefficients: [0.2, -0.1, 0.0, 0.1, 0.0] };
    let mapped =
        SimConfig { truth: PlateTruth { friction_map: map, ..PlateTruth::NOMINAL }, ..SimConfig::default() };
    let on_map = measured(mapped, &at, &[], 4);
    for (i, p) in at.iter().enumerate() {
        let want = map.scale_at([1.0, 0.5], p[0], p[1]);
        let r = norm(on_map[i]) / norm(base[i]);
        assert!((r - want).abs() < 0.02 * want, "part {i} at {p:?}: {r} against the map's {want}");
    }
}

#[test]
fn sensors_read_the_command_while_the_plate_sits_elsewhere() {
    let truth = PlateTruth::worn();
    let cfg = SimConfig { actuator: ActuatorKind::Ideal, truth, ..SimConfig::default() };
    let mut sim = Simulator::new(cfg, &[]).expect("sim");
    let rig = Rig::new(cfg.rig).expect("rig");
    let pose = Pose { x: 1e-3, y: -0.5e-3, theta: 1e-3 };
    let mut cmd = ActuatorCommand::HOME;
    rig.actuator_positions(&pose, &mut cmd.position);
    sim.write(&cmd).expect("write");
    sim.advance();
    let mut state = PlateState::default();
    sim.read(&mut state).expect("read");
    let real = sim.plate_pose();
    let mut stroke = [0.0; MAX_ACTUATORS];
    Rig::new(truth.plant_rig(&cfg.rig)).expect("plant").actuator_positions(&real, &mut stroke);
    // Four actuators, three degrees of freedom: the servos meet the command
    // in the least-squares sense, and each sensor reads its stroke scaled.
    for (i, (read, stroke)) in state.actuator_position.iter().zip(stroke).take(rig.count()).enumerate() {
        assert_eq!(*read, stroke * (1.0 + truth.sensor_scale_error[i]), "sensor {i}");
    }
    // Through the model, the sensors say the plate is about where it was
    // told to be, while it is not.
    let off = |p: Pose| (p.x - pose.x).hypot(p.y - pose.y) + (p.theta - pose.theta).abs();
    assert!(off(state.pose) < 0.2 * off(real), "{:?} {real:?}", state.pose);
    let mut nominal = Simulator::new(SimConfig { truth: PlateTruth::NOMINAL, ..cfg }, &[]).expect("sim");
    nominal.write(&cmd).expect("write");
    nominal.advance();
    assert_eq!(nominal.plate_pose(), rig.pose_from_actuators(&cmd.position));
}
