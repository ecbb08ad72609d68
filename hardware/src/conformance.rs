//! Driver conformance suite, written once for any [`PlateDriver`].
//!
//! Each check takes a factory (so it can build fresh drivers) and panics
//! with a message naming the broken rule; call them from a `#[test]`, or all
//! at once with [`run_all`]. `settle` is how many ticks the driver may take
//! to reach a held command (0 for drivers that land on it every tick).

use crate::{ActuatorCommand, PlateDriver, PlateState, WriteError};
use upm_motion::{MotionParams, PlateMotion, Rig, RigParams, ScheduleEntry};

use crate::playback::play;

fn read<D: PlateDriver>(d: &mut D) -> PlateState {
    let mut s = PlateState::default();
    assert!(d.read(&mut s).is_ok(), "read must succeed on a healthy driver");
    s
}

fn run<D: PlateDriver>(d: &mut D, cmd: &ActuatorCommand, ticks: usize) {
    for _ in 0..ticks {
        assert!(d.write(cmd).is_ok(), "finite command must be accepted");
        d.advance();
    }
}

/// A fresh driver reports home at rest, with sane limits.
pub fn starts_home<D: PlateDriver>(make: impl Fn() -> D) {
    let mut d = make();
    let l = d.limits();
    assert!((3..=crate::MAX_ACTUATORS).contains(&l.count), "actuator count {}", l.count);
    for i in 0..l.count {
        assert!(
            l.stroke[i] > 0.0 && l.velocity[i] > 0.0 && l.force[i] > 0.0,
            "limit of actuator {i} not positive"
        );
    }
    assert!(d.tick_period() > 0.0 && d.tick_period().is_finite());
    let s = read(&mut d);
    assert_eq!(s.pose, crate::Pose::HOME, "fresh driver not at home");
    assert_eq!((s.clamped, s.rejected), (0, 0));
}

/// A held command inside the limits is reached.
pub fn follows_held_command<D: PlateDriver>(make: impl Fn() -> D, settle: usize) {
    let mut d = make();
    let l = d.limits();
    let mut cmd = ActuatorCommand::HOME;
    // A small pure translation along x: both x actuators move the same.
    let rig = Rig::new(RigParams::default()).ok();
    let target = crate::Pose { x: 0.2 * l.stroke[0], y: 0.0, theta: 0.0 };
    match rig {
        Some(r) if r.count() == l.count => r.actuator_positions(&target, &mut cmd.position),
        _ => cmd.position[0] = 0.2 * l.stroke[0],
    }
    run(&mut d, &cmd, settle.max(1) + 1);
    let s = read(&mut d);
    for i in 0..l.count {
        let err = (s.actuator_position[i] - cmd.position[i]).abs();
        assert!(
            err <= 1e-3 * l.stroke[i],
            "actuator {i}: at {} after settling, commanded {}",
            s.actuator_position[i],
            cmd.position[i]
        );
    }
    assert_eq!(s.clamped, 0, "a command inside the limits must not be clamped");
}

/// Commands beyond the limits are clamped (never passed on) and counted:
/// a position beyond the stroke settles at the stroke; forces reported
/// never exceed their limit.
pub fn clamps_beyond_limits<D: PlateDriver>(make: impl Fn() -> D, settle: usize) {
    let mut d = make();
    let l = d.limits();
    let mut cmd = ActuatorCommand::HOME;
    let rig = Rig::new(RigParams::default()).ok().filter(|r| r.count() == l.count);
    // Far beyond the stroke along x (both x actuators consistent).
    match &rig {
        Some(r) => r.actuator_positions(
            &crate::Pose { x: 10.0 * l.stroke[0], y: 0.0, theta: 0.0 },
            &mut cmd.position,
        ),
        None => cmd.position[0] = 10.0 * l.stroke[0],
    }
    run(&mut d, &cmd, settle.max(1) + 1);
    let s = read(&mut d);
    for i in 0..l.count {
        assert!(
            s.actuator_position[i].abs() <= l.stroke[i] * (1.0 + 1e-3),
            "actuator {i} settled beyond its stroke"
        );
    }
    assert!(s.clamped >= 1, "clamp not counted");
    let mut cmd = ActuatorCommand::HOME;
    for i in 0..l.count {
        cmd.velocity[i] = 10.0 * l.velocity[i];
        cmd.force[i] = 10.0 * l.force[i] * if i % 2 == 0 { 1.0 } else { -1.0 };
    }
    for _ in 0..3 {
        assert!(d.write(&cmd).is_ok());
        d.advance();
        let s = read(&mut d);
        for i in 0..l.count {
            assert!(
                s.actuator_force[i].abs() <= l.force[i] * (1.0 + 1e-12),
                "actuator {i}: force beyond limit"
            );
        }
    }
    let after = read(&mut d);
    assert!(after.clamped >= s.clamped + 2 * l.count as u64, "velocity/force clamps not counted");
}

/// Non-finite commands are rejected, counted, and change nothing.
pub fn rejects_non_finite<D: PlateDriver>(make: impl Fn() -> D) {
    let mut d = make();
    let before = read(&mut d);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut cmd = ActuatorCommand::HOME;
        cmd.position[1] = bad;
        assert!(matches!(d.write(&cmd), Err(WriteError::NonFinite { actuator: 1 })), "non-finite accepted");
        d.advance();
    }
    let s = read(&mut d);
    assert_eq!(s.rejected, 3);
    assert!(s.pose.is_finite() && s.velocity.is_finite());
    assert!((s.pose.x - before.pose.x).abs() < 1e-12 && (s.pose.theta - before.pose.theta).abs() < 1e-12);
}

/// `hold` brings the plate back home at rest and says so; a write resumes.
pub fn hold_returns_home<D: PlateDriver>(make: impl Fn() -> D, settle: usize) {
    let mut d = make();
    let l = d.limits();
    let mut cmd = ActuatorCommand::HOME;
    cmd.position[0] = 0.3 * l.stroke[0];
    cmd.position[1] = 0.3 * l.stroke[1];
    run(&mut d, &cmd, settle.max(1));
    d.hold();
    for _ in 0..settle.max(1) + 1 {
        d.advance();
    }
    let s = read(&mut d);
    assert!(s.holding, "holding flag not set");
    let off = s.pose.x.abs() + s.pose.y.abs() + s.pose.theta.abs();
    assert!(off <= 1e-3 * l.stroke[0], "not home after hold: {:?}", s.pose);
    run(&mut d, &cmd, 1);
    assert!(!read(&mut d).holding, "write must end a hold");
}

/// Same commands → bit-identical states.
pub fn deterministic<D: PlateDriver>(make: impl Fn() -> D) {
    let (mut a, mut b) = (make(), make());
    let motion = demo_motion();
    let rig = Rig::new(RigParams::default()).ok();
    let Some(rig) = rig.filter(|r| r.count() == a.limits().count) else { return };
    let (mut sa, mut sb) = (PlateState::default(), PlateState::default());
    for c in 0..3 {
        let start = c * motion.cycle_ticks();
        assert!(play(&mut a, &rig, &motion, start, motion.cycle_ticks(), &mut sa).is_ok());
        assert!(play(&mut b, &rig, &motion, start, motion.cycle_ticks(), &mut sb).is_ok());
        assert_eq!(sa, sb, "runs diverged in cycle {c}");
    }
}

/// Playing whole cycles of a closed motion brings the plate home (to `tol`
/// in pose units; 1e-12 for a driver that lands on its commands). A
/// driver whose readings lag its commands by `latency_ticks` (a fieldbus:
/// transport and interpolation) is read that many ticks into the next
/// cycle, when what it reports is the end of the cycle before.
pub fn closed_motion_returns_home<D: PlateDriver>(make: impl Fn() -> D, tol: f64, latency_ticks: u64) {
    let mut d = make();
    let motion = demo_motion();
    let rig = Rig::new(RigParams::default()).ok();
    let Some(rig) = rig.filter(|r| r.count() == d.limits().count) else { return };
    let mut s = PlateState::default();
    let n = motion.cycle_ticks();
    assert!(
        latency_ticks < n / 4,
        "a latency of {latency_ticks} ticks is a quarter of the demo cycle or more"
    );
    for c in 0..4 {
        let (start, ticks) = if c == 0 { (0, n + latency_ticks) } else { (c * n + latency_ticks, n) };
        assert!(play(&mut d, &rig, &motion, start, ticks, &mut s).is_ok());
        let off = s.pose.x.abs().max(s.pose.y.abs()).max(s.pose.theta.abs());
        assert!(off <= tol, "cycle {c}: pose {:?} not home within {tol:e}", s.pose);
        assert_eq!(s.clamped, 0, "the demo motion is within limits and must not be clamped");
    }
}

/// The paper's §3.1 schedule (K = .58, −.39, .48, −.095).
pub fn demo_motion() -> PlateMotion {
    let entries = [
        ScheduleEntry { center: [1.0, 0.5], k: 0.48 },
        ScheduleEntry { center: [-1.0, 0.5], k: -0.095 },
        ScheduleEntry { center: [-1.0, -0.5], k: 0.58 },
        ScheduleEntry { center: [1.0, -0.5], k: -0.39 },
    ];
    let mut m = PlateMotion::new(MotionParams::default()).unwrap_or_else(|e| panic!("default params: {e}"));
    m.set_schedule(&entries).unwrap_or_else(|e| panic!("demo schedule: {e}"));
    m
}

/// How closely a driver is held to its commands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Ticks to reach a held command.
    pub settle: usize,
    /// How close to home whole cycles end (pose units).
    pub home: f64,
    /// Ticks by which readings lag commands.
    pub latency_ticks: u64,
}

/// Every check above, for a driver without latency.
pub fn run_all<D: PlateDriver>(make: impl Fn() -> D, settle: usize, home_tol: f64) {
    run_all_with(make, Tolerances { settle, home: home_tol, latency_ticks: 0 });
}

/// Every check above.
pub fn run_all_with<D: PlateDriver>(make: impl Fn() -> D, t: Tolerances) {
    let Tolerances { settle, home: home_tol, latency_ticks } = t;
    starts_home(&make);
    follows_held_command(&make, settle);
    clamps_beyond_limits(&make, settle);
    rejects_non_finite(&make);
    hold_returns_home(&make, settle);
    deterministic(&make);
    closed_motion_returns_home(&make, home_tol, latency_ticks);
}
