//! Real-time factor of the simulator: 10 parts, plate at 10 kHz, one core,
//! the full lock-step loop (motion sampling + kinematics + driver write +
//! simulator step). Usage: sim_speed [seconds] [case index]
use std::time::Instant;

use drivers::conformance::demo_motion;
use drivers::lockstep::play;
use drivers::{PartSpec, Shape, SimConfig, Simulator};
use rt_core::driver::PlateState;
use rt_core::motion::Rig;

fn parts(shape: Shape) -> Vec<PartSpec> {
    (0..10)
        .map(|i| PartSpec {
            shape,
            mass: 0.04,
            position: [-0.8 + 0.17 * i as f64, 0.3 * (i as f64 * 1.7).sin()],
            angle: 0.0,
        })
        .collect()
}

fn main() {
    let seconds: f64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(20.0);
    let mut square = [[0.0; 2]; drivers::sim::MAX_POLYGON_VERTICES];
    square[..4].copy_from_slice(&[[-0.03, -0.03], [0.03, -0.03], [0.03, 0.03], [-0.03, 0.03]]);
    let cases = [
        ("no parts (plate + loop only)", Shape::Point { radius: -1.0 }),
        ("10 point parts", Shape::Point { radius: 0.01 }),
        ("10 discs (6 contacts)", Shape::Disc { radius: 0.03 }),
        ("10 squares (8 contacts)", Shape::Polygon { vertices: square, count: 4 }),
    ];
    let only: Option<usize> = std::env::args().nth(2).and_then(|s| s.parse().ok());
    for (i, (name, shape)) in cases.into_iter().enumerate() {
        if only.is_some_and(|o| o != i) {
            continue;
        }
        let cfg = SimConfig::default();
        let ps = if matches!(shape, Shape::Point { radius } if radius < 0.0) { vec![] } else { parts(shape) };
        let mut sim = Simulator::new(cfg, &ps).expect("sim");
        let rig = Rig::new(cfg.rig).expect("rig");
        let motion = demo_motion();
        let ticks = (seconds * cfg.tick_hz) as u64;
        let mut st = PlateState::default();
        let t0 = Instant::now();
        play(&mut sim, &rig, &motion, 0, ticks, &mut st).expect("read");
        let wall = t0.elapsed().as_secs_f64();
        println!(
            "{name:26} sim {seconds:.1} s in {wall:.3} s wall: {:.0}x real time ({:.0} ns/tick)",
            seconds / wall,
            wall / ticks as f64 * 1e9
        );
    }
}
