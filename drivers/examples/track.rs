use drivers::{ActuatorModel, PartSpec, SimConfig, Simulator};
use rt_core::driver::{ActuatorCommand, PlateDriver};
use rt_core::motion::{MotionParams, PlateMotion, Rig};

fn run(model: ActuatorModel) -> Vec<[f64; 2]> {
    let centers = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]];
    let k = [0.58, -0.39, 0.48, -0.095];
    let mut mp = MotionParams::default();
    mp.displacement = 2e-3;
    let mut motion = PlateMotion::new(mp).unwrap();
    motion.set_from_solution(&centers, &k, &[2, 3, 0, 1]).unwrap();
    let mut cfg = SimConfig::default();
    cfg.actuator = model;
    let mut sim = Simulator::new(cfg, &[] as &[PartSpec]).unwrap();
    let rig = Rig::new(cfg.rig).unwrap();
    let h = 1e-4;
    let mut cmd = ActuatorCommand::HOME;
    let mut now = motion.sample_tick(0);
    let p = [0.5, 0.0];
    let mut out = vec![sim.plate_velocity().at(&sim.plate_pose(), p)];
    for t in 0..320u64 {
        let mut next = motion.sample_tick(t + 1);
        next.acceleration.x = (next.velocity.x - now.velocity.x) / h;
        next.acceleration.y = (next.velocity.y - now.velocity.y) / h;
        next.acceleration.theta = (next.velocity.theta - now.velocity.theta) / h;
        rig.command(&next, &mut cmd);
        sim.write(&cmd).unwrap();
        sim.advance();
        out.push(sim.plate_velocity().at(&sim.plate_pose(), p));
        now = next;
    }
    out
}

fn force(v: &[[f64; 2]], from: usize, to: usize) -> [f64; 2] {
    let mut f = [0.0; 2];
    let n = 1000;
    for t in from..to {
        for s in 0..n {
            let a = (s as f64 + 0.5) / n as f64;
            let x = v[t][0] + (v[t + 1][0] - v[t][0]) * a;
            let y = v[t][1] + (v[t + 1][1] - v[t][1]) * a;
            let m = x.hypot(y);
            if m > 0.0 {
                f[0] += x / m;
                f[1] += y / m;
            }
        }
    }
    let tot = ((to - from) * n) as f64;
    [0.1 * f[0] / tot, 0.1 * f[1] / tot]
}

fn main() {
    let a = run(ActuatorModel::Ideal);
    let b = run(ActuatorModel::SecondOrder { bandwidth_hz: 100.0, damping: 0.7 });
    for t in 110..165 {
        println!("{t}: ideal {:+.5?} so {:+.5?}", a[t], b[t]);
    }
    for s in 0..8 {
        println!(
            "slot {s}: ideal {:?} so {:?}",
            force(&a, s * 40, s * 40 + 40),
            force(&b, s * 40, s * 40 + 40)
        );
    }
    println!("cycle2: ideal {:?} so {:?}", force(&a, 160, 320), force(&b, 160, 320));
}
