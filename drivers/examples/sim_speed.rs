//! Real-time factor of the simulator: 10 parts, plate at 10 kHz, one core.
//! Two figures: the full lock-step loop (motion sampling + kinematics +
//! driver write + simulator step + read), and the driver alone (write +
//! step + read) replaying one recorded cycle of commands. Usage: sim_speed [seconds] [case index] [profile]
use std::time::Instant;

use drivers::{BodyShape, PartSpec, SimConfig, Simulator};
use upm_hardware::PlateState;
use upm_hardware::conformance::demo_motion;
use upm_hardware::playback::{play, record_commands, replay};
use upm_motion::Rig;

fn parts(shape: BodyShape) -> Vec<PartSpec> {
    (0..10)
        .map(|i| PartSpec {
            shape,
            mass: 0.04,
            position: [-0.8 + 0.17 * i as f64, 0.3 * (i as f64 * 1.7).sin()],
            angle: 0.0,
        })
        .collect()
}

/// Runs per case; the median is reported.
const REPEATS: usize = 7;

fn main() {
    let seconds: f64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(20.0);
    let mut square = [[0.0; 2]; drivers::sim::MAX_POLYGON_VERTICES];
    square[..4].copy_from_slice(&[[-0.03, -0.03], [0.03, -0.03], [0.03, 0.03], [-0.03, 0.03]]);
    let cases = [
        ("no parts (plate + loop only)", BodyShape::Point { radius: -1.0 }),
        ("10 point parts", BodyShape::Point { radius: 0.01 }),
        ("10 discs (uniform face)", BodyShape::Disc { radius: 0.03 }),
        ("10 squares (8 contacts)", BodyShape::Polygon { vertices: square, count: 4 }),
    ];
    let only: Option<usize> = std::env::args().nth(2).and_then(|s| s.parse().ok());
    // "profile": one run, no warm-up (for callgrind's instruction counts).
    let profile = std::env::args().nth(3).is_some_and(|a| a == "profile");
    for (i, (name, shape)) in cases.into_iter().enumerate() {
        if only.is_some_and(|o| o != i) {
            continue;
        }
        let cfg = SimConfig::default();
        let ps =
            if matches!(shape, BodyShape::Point { radius } if radius < 0.0) { vec![] } else { parts(shape) };
        let rig = Rig::new(cfg.rig).expect("rig");
        let motion = demo_motion();
        let ticks = (seconds * cfg.tick_hz) as u64;
        let commands = record_commands(&rig, &motion, 1.0 / cfg.tick_hz, motion.cycle_ticks());
        // Full loop (motion sampling + kinematics + driver), then the driver
        // alone replaying one recorded cycle of commands.
        let run = |driver_only: bool| {
            let mut sim = Box::new(Simulator::new(cfg, &ps).expect("sim"));
            let mut st = PlateState::default();
            let t0 = Instant::now();
            if driver_only {
                replay(&mut *sim, &commands, ticks, &mut st).expect("read");
            } else {
                play(&mut *sim, &rig, &motion, 0, ticks, &mut st).expect("read");
            }
            t0.elapsed().as_secs_f64()
        };
        // Warm up first (this VM's clock ramps up over ~0.1 s of load), then
        // take the median of REPEATS fresh runs of each, interleaved.
        let warm = Instant::now();
        while !profile && warm.elapsed().as_secs_f64() < 0.3 {
            run(false);
        }
        let repeats = if profile { 1 } else { REPEATS };
        let (mut full, mut alone): (Vec<f64>, Vec<f64>) =
            (0..repeats).map(|_| (run(false), run(true))).unzip();
        full.sort_by(f64::total_cmp);
        alone.sort_by(f64::total_cmp);
        let (f, a) = (full[repeats / 2], alone[repeats / 2]);
        let ns = |w: f64| w / ticks as f64 * 1e9;
        println!(
            "{name:26} full loop {:4.0}x ({:4.0} ns/tick, best {:4.0}x) | driver alone {:4.0}x ({:4.0} ns/tick, best {:4.0}x)   [median of {repeats}, {seconds} s]",
            seconds / f,
            ns(f),
            seconds / full[0],
            seconds / a,
            ns(a),
            seconds / alone[0],
        );
    }
}
