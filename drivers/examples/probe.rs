use drivers::lockstep::play;
use drivers::{ActuatorModel, PartSpec, PartState, Shape, SimConfig, Simulator};
use rt_core::driver::PlateState;
use rt_core::motion::{MotionParams, PlateMotion, Rig};
use rt_core::solver::field::cycle_force;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let slot_ticks: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(40);
    let disp: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1e-3);
    let ideal = args.get(3).map(|s| s == "ideal").unwrap_or(true);
    let centers = [[-1.0, -0.5], [1.0, -0.5], [1.0, 0.5], [-1.0, 0.5]];
    let k = [0.58, -0.39, 0.48, -0.095];
    let order = [2u16, 3, 0, 1];
    let mut mp = MotionParams::default();
    mp.slot_ticks = slot_ticks;
    mp.displacement = disp;
    let mut motion = PlateMotion::new(mp).unwrap();
    motion.set_from_solution(&centers, &k, &order).unwrap();
    let mut cfg = SimConfig::default();
    if ideal {
        cfg.actuator = ActuatorModel::Ideal;
    } else if let Some(bw) = args.get(3).and_then(|s| s.parse::<f64>().ok()) {
        cfg.actuator = ActuatorModel::SecondOrder { bandwidth_hz: bw, damping: 0.7 };
    }
    cfg.collisions = false;
    cfg.substeps = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1);
    let pos = [[0.5, 0.0], [-0.75, 0.25]];
    let mu_m_g = 0.1;
    let m = mu_m_g / (cfg.mu_kinetic * cfg.gravity);
    let specs: Vec<_> = pos
        .iter()
        .map(|&p| PartSpec { shape: Shape::Point { radius: 0.0 }, mass: m, position: p, angle: 0.0 })
        .collect();
    let mut sim = Simulator::new(cfg, &specs).unwrap();
    let rig = Rig::new(cfg.rig).unwrap();
    println!("rig check {:?}", rig.check_motion(&motion));
    let mut st = PlateState::default();
    let t = motion.cycle_duration();
    let cycles = 5;
    let mut acc = vec![[0.0; 2]; 2];
    for c in 0..cycles {
        for (i, &p) in pos.iter().enumerate() {
            sim.set_part(i, PartState { position: p, ..Default::default() });
        }
        play(&mut sim, &rig, &motion, c * motion.cycle_ticks(), motion.cycle_ticks(), &mut st).unwrap();
        for i in 0..2 {
            let v = sim.parts()[i].velocity;
            acc[i][0] += m * v[0] / t / cycles as f64;
            acc[i][1] += m * v[1] / t / cycles as f64;
        }
    }
    println!("pose end {:?}", st.pose);
    for i in 0..2 {
        let want = cycle_force(&k, &centers, mu_m_g, pos[i]);
        let e = ((acc[i][0] - want[0]).powi(2) + (acc[i][1] - want[1]).powi(2)).sqrt();
        println!(
            "part {i}: sim {:?} model {:?} err {:.5} ({:.2}% of mu_m_g)",
            acc[i],
            want,
            e,
            100.0 * e / mu_m_g
        );
    }
    println!("{:?}", sim.counters());
}
