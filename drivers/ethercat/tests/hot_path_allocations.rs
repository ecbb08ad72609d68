//! After start-up, the EtherCAT driver's read / write / hold / advance
//! allocate nothing, on the healthy path and on every fault path (a drive
//! fault and its reset, lost frames, a cut cable, garbled answers). Shown
//! able to fail: a planted allocation in the same closure is counted.

mod common;

use drivers::{BodyShape, PartSpec, SimConfig};
use ethercat_sim::SimulatedRig;
use rt_core::alloc_count::{RtAllocCounter, allocations_in, counter_installed};
use upm_ethercat::EthercatDriver;
use upm_hardware::conformance::demo_motion;
use upm_hardware::playback::play;
use upm_hardware::{PlateDriver, PlateState};
use upm_motion::Rig;

#[global_allocator]
static A: RtAllocCounter = RtAllocCounter;

fn driver() -> EthercatDriver<SimulatedRig> {
    let parts =
        [PartSpec { shape: BodyShape::Disc { radius: 0.03 }, mass: 0.04, position: [0.2, 0.1], angle: 0.0 }];
    let p = common::params();
    EthercatDriver::start(common::chain(&p, &parts), p, SimConfig::default().rig)
        .unwrap_or_else(|e| panic!("{e}"))
}

fn hold<D: PlateDriver>(d: &mut D, ticks: usize) {
    let mut s = PlateState::default();
    for _ in 0..ticks {
        let _ = d.read(&mut s);
        d.hold();
        d.advance();
    }
}

#[test]
fn exchanges_allocate_nothing_on_any_path() {
    assert!(counter_installed(), "the counter must see allocations");
    let mut d = driver();
    let rig = Rig::new(SimConfig::default().rig).expect("rig");
    let m = demo_motion();
    let mut s = PlateState::default();
    let mut run = |d: &mut EthercatDriver<SimulatedRig>, planted: bool| {
        for c in 0..5 {
            let _ = play(d, &rig, &m, c * m.cycle_ticks(), m.cycle_ticks(), &mut s);
        }
        let _ = d.with_wire(|w| w.chain.devices[2].drive.fault());
        hold(d, 200);
        let _ = d.with_wire(|w| w.chain.lose_frames(4));
        hold(d, 100);
        let _ = d.with_wire(|w| w.chain.cut_after(1));
        hold(d, 50);
        let _ = d.with_wire(|w| w.chain.cut_after(usize::MAX));
        hold(d, 100);
        let _ = d.with_wire(|w| w.chain.garble_frames(4));
        hold(d, 100);
        if planted {
            std::hint::black_box(vec![0u8; 8]);
        }
    };
    let ((), allocated) = allocations_in(|| run(&mut d, false));
    let h = d.health();
    assert!(h.faults[2] == 1 && h.lost_frames >= 18 && h.bad_frames >= 4, "the fault paths ran: {h:?}");
    // Every exchange completed within its poll, garbled answers included:
    // none reached ethercrab's timer (a syscall, maybe a lock).
    assert_eq!(d.unfinished_exchanges(), 0);
    assert_eq!(allocated, 0, "the EtherCAT hot path allocated");
    let ((), planted) = allocations_in(|| run(&mut d, true));
    assert!(planted >= 1, "a planted allocation must be counted");
}
