//! Part–part impacts conserve linear momentum; the fence keeps parts on.

use drivers::{ActuatorKind, BodyShape, PartSpec, PartState, SimConfig, Simulator};
use upm_hardware::PlateDriver;

fn disc(p: [f64; 2], m: f64) -> PartSpec {
    PartSpec { shape: BodyShape::Disc { radius: 0.03 }, mass: m, position: p, angle: 0.0 }
}

#[test]
fn collision_conserves_momentum() {
    // Friction made negligible so only the impact changes momentum.
    let cfg = SimConfig {
        actuator: ActuatorKind::Ideal,
        mu_kinetic: 1e-12,
        mu_static: 1e-12,
        part_restitution: 1.0,
        ..SimConfig::default()
    };
    let mut s = Simulator::new(cfg, &[disc([-0.1, 0.0], 0.04), disc([0.1, 0.01], 0.1)]).expect("sim");
    assert!(s.set_part(0, PartState { position: [-0.1, 0.0], velocity: [1.0, 0.0], ..PartState::default() }));
    assert!(
        s.set_part(1, PartState { position: [0.1, 0.01], velocity: [-0.5, 0.0], ..PartState::default() })
    );
    let p = |s: &mut Simulator| {
        let ps = s.parts();
        [
            0.04 * ps[0].velocity[0] + 0.1 * ps[1].velocity[0],
            0.04 * ps[0].velocity[1] + 0.1 * ps[1].velocity[1],
        ]
    };
    let e = |s: &mut Simulator| {
        let ps = s.parts();
        0.02 * (ps[0].velocity[0].powi(2) + ps[0].velocity[1].powi(2))
            + 0.05 * (ps[1].velocity[0].powi(2) + ps[1].velocity[1].powi(2))
    };
    let (p0, e0) = (p(&mut s), e(&mut s));
    for _ in 0..2000 {
        s.advance();
    }
    assert!(s.counters().collisions >= 1, "no impact happened");
    let p1 = p(&mut s);
    assert!((p1[0] - p0[0]).abs() < 1e-9 && (p1[1] - p0[1]).abs() < 1e-9, "{p0:?} → {p1:?}");
    assert!((e(&mut s) - e0).abs() < 1e-9 * e0, "elastic impact must keep energy");
    assert!(s.parts()[1].velocity[0] > 0.0, "the heavy disc must be pushed back");
}

#[test]
fn fence_keeps_parts_on_the_plate() {
    let cfg = SimConfig { actuator: ActuatorKind::Ideal, ..SimConfig::default() };
    let mut s = Simulator::new(cfg, &[disc([0.9, 0.0], 0.04)]).expect("sim");
    assert!(s.set_part(0, PartState { position: [0.9, 0.0], velocity: [2.0, 0.0], ..PartState::default() }));
    for _ in 0..1000 {
        s.advance();
        let x = s.parts()[0].position[0];
        assert!(x <= 1.0 - 0.03 + 1e-12, "part left the plate: {x}");
    }
    assert!(s.counters().fence_hits >= 1);
    assert!(s.parts()[0].velocity[0] <= 0.0);
}
