//! Same config + seed → bit-identical runs; a different seed differs.

use drivers::{BodyShape, PartSpec, PartState, SimConfig, Simulator};
use upm_hardware::PlateState;
use upm_hardware::conformance::demo_motion;
use upm_hardware::playback::play;
use upm_motion::Rig;

fn parts() -> Vec<PartSpec> {
    let mut v = Vec::new();
    for i in 0..10 {
        let (x, y) = (-0.8 + 0.17 * i as f64, 0.3 * ((i as f64) * 1.7).sin());
        let shape = match i % 3 {
            0 => BodyShape::Point { radius: 0.01 },
            1 => BodyShape::Disc { radius: 0.04 },
            _ => {
                let mut vs = [[0.0; 2]; drivers::sim::MAX_POLYGON_VERTICES];
                vs[..4].copy_from_slice(&[[-0.03, -0.02], [0.03, -0.02], [0.03, 0.02], [-0.03, 0.02]]);
                BodyShape::Polygon { vertices: vs, count: 4 }
            }
        };
        v.push(PartSpec { shape, mass: 0.04, position: [x, y], angle: 0.1 * i as f64 });
    }
    v
}

fn record(seed: u64) -> Vec<PartState> {
    let cfg = SimConfig { seed, force_noise: 5.0, ..SimConfig::default() };
    let mut s = Simulator::new(cfg, &parts()).expect("sim");
    let rig = Rig::new(cfg.rig).expect("rig");
    let m = demo_motion();
    let mut st = PlateState::default();
    let mut out = Vec::new();
    for c in 0..30 {
        play(&mut s, &rig, &m, c * m.cycle_ticks(), m.cycle_ticks(), &mut st).expect("read");
        out.extend_from_slice(s.parts());
    }
    out
}

#[test]
fn two_runs_are_bit_identical() {
    let (a, b) = (record(7), record(7));
    assert!(a.iter().zip(&b).all(|(x, y)| x.position[0].to_bits() == y.position[0].to_bits()
        && x.position[1].to_bits() == y.position[1].to_bits()
        && x.angle.to_bits() == y.angle.to_bits()
        && x.velocity[0].to_bits() == y.velocity[0].to_bits()));
    assert_eq!(a, b);
}

#[test]
fn seed_matters_when_noise_is_on() {
    assert_ne!(record(7), record(8));
}

/// With collisions and the fence off, parts do not interact: each part's
/// run among points, discs of other sizes and polygons is bit-identical to
/// its run alone. (Catches a lane stepped with another part's body or
/// state.)
#[test]
fn a_part_moves_the_same_alone_and_among_others() {
    let mut specs = parts();
    for (i, p) in specs.iter_mut().enumerate() {
        if let BodyShape::Disc { radius } = &mut p.shape {
            *radius = 0.01 + 0.005 * i as f64;
        }
    }
    let cfg = SimConfig { collisions: false, fence: false, ..SimConfig::default() };
    let run = |specs: &[PartSpec]| {
        let mut s = Simulator::new(cfg, specs).expect("sim");
        let rig = Rig::new(cfg.rig).expect("rig");
        let m = demo_motion();
        let mut st = PlateState::default();
        play(&mut s, &rig, &m, 0, 5 * m.cycle_ticks(), &mut st).expect("read");
        s.parts().to_vec()
    };
    let together = run(&specs);
    for (i, spec) in specs.iter().enumerate() {
        assert_eq!(run(core::slice::from_ref(spec))[0], together[i], "part {i} ({:?})", spec.shape);
    }
    assert!(together.iter().zip(&specs).all(|(p, s)| p.position != s.position));
}
