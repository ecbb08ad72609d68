//! Distributed clocks over the simulated chain: when every drive offers
//! them, start-up measures the propagation delays, sets each clock's
//! offset, and runs the drives on SYNC0 at the bus cycle; each exchange
//! carries the reference's time to the others (FRMW). Checked from the
//! drives' side: their system times agree, every bus cycle brings one
//! SYNC0 event with fresh outputs, and lost frames show as SYNC0 events
//! without data. Without DC (turned off) the drives run free.

use drivers::{SimConfig, Simulator};
use ethercat_sim::SimulatedRig;
use ethercat_sim::chain::HOP_NS;
use rt_core::driver::{PlateDriver, PlateState};
use upm_ethercat::{EthercatDriver, EthercatParams};

fn start(distributed_clocks: bool) -> EthercatDriver<SimulatedRig> {
    let cfg = SimConfig::default();
    let p = EthercatParams {
        tick_hz: cfg.tick_hz,
        count: cfg.rig.count,
        distributed_clocks,
        ..EthercatParams::default()
    };
    let sim = Simulator::new(cfg, &[]).expect("default sim");
    let rig = SimulatedRig::new(sim, p.counts_per_metre, p.rated_force_n, p.cycle_divisor);
    EthercatDriver::start(rig, p, cfg.rig).unwrap_or_else(|e| panic!("{e}"))
}

fn hold(d: &mut EthercatDriver<SimulatedRig>, cycles: u32) {
    for _ in 0..cycles * EthercatParams::default().cycle_divisor {
        d.hold();
        d.advance();
    }
}

/// Per drive: SYNC0 events, those without fresh data, system time, and
/// the difference to the reference the last FRMW left.
fn drives(d: &EthercatDriver<SimulatedRig>) -> Vec<(u64, u64, u64, i64)> {
    d.with_wire(|w| {
        w.chain
            .devices
            .iter()
            .map(|s| (s.sync0_events, s.sync0_missed, s.system_time(), s.system_time_difference()))
            .collect()
    })
    .expect("wire")
}

#[test]
fn drives_run_on_sync0_with_agreeing_clocks() {
    let mut d = start(true);
    // Past SYNC0's start delay (100 ms = 100 bus cycles at 1 kHz).
    hold(&mut d, 200);
    let before = drives(&d);
    hold(&mut d, 100);
    let after = drives(&d);
    let reference = after[0].2;
    for (i, (b, a)) in before.iter().zip(&after).enumerate() {
        assert_eq!(a.0 - b.0, 100, "drive {i}: one SYNC0 event per bus cycle");
        assert_eq!(a.1, 0, "drive {i}: no SYNC0 event without fresh outputs");
        // The clocks agree to within the frame's passage along the chain
        // (the registers are read as the frame passes each device).
        let skew = a.2.abs_diff(reference);
        assert!(
            skew <= 2 * HOP_NS * after.len() as u64,
            "drive {i}: system time {skew} ns from the reference"
        );
        if i > 0 {
            assert!(a.3.unsigned_abs() < 10, "drive {i}: {} ns from the reference's time", a.3);
        }
    }
    let dc = d.distributed_clocks().expect("the driver runs on distributed clocks");
    assert!(dc.after_sync0_ns < 1_000_000, "{dc:?}");
    assert!(d.read(&mut PlateState::default()).is_ok());

    // Lost frames: SYNC0 keeps ticking, the drives see it pass without data.
    assert!(d.with_wire(|w| w.chain.lose_frames(3)).is_some());
    hold(&mut d, 10);
    let lost = drives(&d);
    for (i, (a, l)) in after.iter().zip(&lost).enumerate() {
        assert_eq!((l.0 - a.0, l.1 - a.1), (10, 3), "drive {i}: events, and events without data");
    }
    assert!(d.read(&mut PlateState::default()).is_ok(), "recovered");
}

#[test]
fn without_distributed_clocks_the_drives_run_free() {
    let mut d = start(false);
    hold(&mut d, 200);
    assert_eq!(d.distributed_clocks(), None);
    assert!(drives(&d).iter().all(|s| s.0 == 0 && s.1 == 0), "no SYNC0 configured");
    assert!(d.read(&mut PlateState::default()).is_ok());
}
