//! read / write / advance and motion sampling allocate nothing.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use drivers::conformance::demo_motion;
use drivers::playback::play;
use drivers::{PartSpec, Shape, SimConfig, Simulator};
use rt_core::driver::PlateState;
use rt_core::motion::Rig;

struct Counting;
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
}

#[global_allocator]
static A: Counting = Counting;

#[test]
fn lockstep_loop_does_not_allocate() {
    let parts: Vec<_> = (0..10)
        .map(|i| PartSpec {
            shape: if i % 2 == 0 { Shape::Point { radius: 0.01 } } else { Shape::Disc { radius: 0.03 } },
            mass: 0.04,
            position: [-0.8 + 0.16 * i as f64, 0.05 * i as f64 - 0.2],
            angle: 0.0,
        })
        .collect();
    let cfg = SimConfig::default();
    let mut s = Simulator::new(cfg, &parts).expect("sim");
    let rig = Rig::new(cfg.rig).expect("rig");
    let mut m = demo_motion();
    let mut st = PlateState::default();
    let before = ALLOCS.load(Ordering::SeqCst);
    for c in 0..20 {
        play(&mut s, &rig, &m, c * m.cycle_ticks(), m.cycle_ticks(), &mut st).expect("read");
    }
    let entries = [rt_core::motion::ScheduleEntry { center: [1.0, 0.5], k: 0.3 }];
    m.set_schedule(&entries).expect("playable");
    let _ = m.sample_tick(3);
    assert_eq!(ALLOCS.load(Ordering::SeqCst) - before, 0, "hot path allocated");
}
