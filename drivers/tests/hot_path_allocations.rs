//! read / write / advance and motion sampling allocate nothing.

use drivers::{BodyShape, PartSpec, SimConfig, Simulator};
use upm_hardware::PlateState;
use upm_hardware::conformance::demo_motion;
use upm_hardware::playback::{play, play_estimating};
use upm_motion::{InertiaEstimate, InertiaParams, Rig};

use rt_core::alloc_count::{RtAllocCounter, allocations_in};

#[global_allocator]
static A: RtAllocCounter = RtAllocCounter;

#[test]
fn lockstep_loop_does_not_allocate() {
    let parts: Vec<_> = (0..10)
        .map(|i| PartSpec {
            shape: if i % 2 == 0 {
                BodyShape::Point { radius: 0.01 }
            } else {
                BodyShape::Disc { radius: 0.03 }
            },
            mass: 0.04,
            position: [-0.8 + 0.16 * i as f64, 0.05 * i as f64 - 0.2],
            angle: 0.0,
        })
        .collect();
    let cfg = SimConfig::default();
    let mut s = Simulator::new(cfg, &parts).expect("sim");
    let mut rig = Rig::new(cfg.rig).expect("rig");
    let mut estimate = InertiaEstimate::new(InertiaParams::default());
    let mut m = demo_motion();
    let mut st = PlateState::default();
    assert!(rt_core::alloc_count::counter_installed(), "the counter must see allocations");
    let ((), allocated) = allocations_in(|| {
        for c in 0..20 {
            play(&mut s, &rig, &m, c * m.cycle_ticks(), m.cycle_ticks(), &mut st).expect("read");
        }
        // With the motor loop's feed-forward estimate, as `bench calibration` plays.
        for c in 20..30 {
            let n = m.cycle_ticks();
            play_estimating(&mut s, &rig, &m, c * n, n, &mut st, Some(&mut estimate)).expect("read");
            rig.set_inertia_scale(estimate.end_cycle());
        }
        let entries = [upm_motion::ScheduleEntry { center: [1.0, 0.5], k: 0.3 }];
        m.set_schedule(&entries).expect("playable");
        let _ = m.sample_tick(3);
    });
    assert_eq!(allocated, 0, "hot path allocated");
    assert_eq!(estimate.updates(), 10, "the estimate ran");
}
