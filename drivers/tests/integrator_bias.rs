//! The fixed-step friction integrator is not biased: average forces at one
//! substep per 10 kHz tick match a 32× finer integration to < 0.5 % of μmg.

use drivers::{BodyShape, PartSpec, PartState, SimConfig, Simulator};
use upm_hardware::PlateState;
use upm_hardware::conformance::demo_motion;
use upm_hardware::playback::play;
use upm_motion::Rig;

fn average_forces(substeps: u32) -> Vec<[f64; 2]> {
    let cfg = SimConfig { substeps, collisions: false, ..SimConfig::default() };
    let mass = 0.1 / (cfg.mu_kinetic * cfg.gravity);
    let pos = [[0.5, 0.0], [-0.75, 0.25], [0.1, -0.3]];
    let specs: Vec<_> = pos
        .iter()
        .map(|&p| PartSpec { shape: BodyShape::Point { radius: 0.0 }, mass, position: p, angle: 0.0 })
        .collect();
    let mut s = Simulator::new(cfg, &specs).expect("sim");
    let rig = Rig::new(cfg.rig).expect("rig");
    let m = demo_motion();
    let mut st = PlateState::default();
    let mut f = vec![[0.0; 2]; pos.len()];
    for c in 0..3 {
        for (i, &p) in pos.iter().enumerate() {
            s.set_part(i, PartState { position: p, ..PartState::default() });
        }
        play(&mut s, &rig, &m, c * m.cycle_ticks(), m.cycle_ticks(), &mut st).expect("read");
        for (fi, p) in f.iter_mut().zip(s.parts()) {
            fi[0] += mass * p.velocity[0] / m.cycle_duration() / 3.0;
            fi[1] += mass * p.velocity[1] / m.cycle_duration() / 3.0;
        }
    }
    f
}

#[test]
fn one_substep_matches_fine_integration() {
    let (coarse, fine) = (average_forces(1), average_forces(32));
    for (c, f) in coarse.iter().zip(&fine) {
        let d = (c[0] - f[0]).hypot(c[1] - f[1]);
        println!("coarse {c:?} fine {f:?} diff/μmg {:.4}%", 100.0 * d / 0.1);
        assert!(d < 0.005 * 0.1, "integrator bias {d:e} ≥ 0.5 % of μmg");
    }
}
