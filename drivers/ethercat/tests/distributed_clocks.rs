//! Distributed clocks over the simulated chain: when every drive offers
//! them, start-up measures the propagation delays, sets each clock's
//! offset, and runs the drives on SYNC0 at the bus cycle; each exchange
//! carries the reference's time to the others (FRMW). Checked from the
//! drives' side: their system times agree, every bus cycle brings one
//! SYNC0 event with fresh outputs, and lost frames show as SYNC0 events
//! without data. Without DC (turned off) the drives run free.

mod common;

use drivers::SimConfig;
use ethercat_sim::chain::HOP_NS;
use ethercat_sim::{ChainTime, SimulatedRig};
use upm_ethercat::{EthercatDriver, EthercatParams};
use upm_hardware::{PlateDriver, PlateState};

fn start(distributed_clocks: bool) -> EthercatDriver<SimulatedRig> {
    let p = EthercatParams { distributed_clocks, ..common::params() };
    EthercatDriver::start(common::chain(&p, &[]), p, SimConfig::default().rig)
        .unwrap_or_else(|e| panic!("{e}"))
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
    // Past SYNC0's start delay (100 ms: 334 bus cycles at 3.3 kHz).
    hold(&mut d, 1000);
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
    assert!(d.distributed_clocks().is_some(), "the driver runs on distributed clocks");
    assert!(d.health().sync0_phase_ns.is_some(), "and reports the phase");
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
    hold(&mut d, 1000);
    assert_eq!((d.distributed_clocks(), d.health().sync0_phase_ns), (None, None));
    assert!(drives(&d).iter().all(|s| s.0 == 0 && s.1 == 0), "no SYNC0 configured");
    assert!(d.read(&mut PlateState::default()).is_ok());
}

/// Ticks of a motor loop on a hand-set clock that the chain keeps time by,
/// the reference drive's crystal running 50 ppm fast: with `follow`, the
/// loop takes the driver's phase corrections as the core's motor loop
/// does. Returns SYNC0 events without fresh data in the last half, and
/// the last frame's phase after SYNC0 (ns).
fn run_on_a_drifting_bus(follow: bool) -> (u64, u64, u64) {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
    let cfg = SimConfig::default();
    let p = common::params();
    let clock = Arc::new(AtomicU64::new(1_000_000_000));
    let mut rig = common::chain(&p, &[]);
    let source = clock.clone();
    rig.chain_time = ChainTime::Source(Box::new(move || source.load(Relaxed)));
    rig.chain.devices[0].drift_ppb = 50_000;
    let mut d = EthercatDriver::start(rig, p, cfg.rig).unwrap_or_else(|e| panic!("{e}"));
    let period = (1e9 / cfg.tick_hz).round() as u64;
    let ticks = (20.0 * cfg.tick_hz) as u64;
    let mut deadline = clock.load(Relaxed);
    let mut missed_at_half = 0;
    let mut x = 7u64;
    for tick in 0..ticks {
        // Wake-ups 0–30 µs late, as on this VM.
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        clock.store(deadline + x % 30_000, Relaxed);
        d.hold();
        d.advance();
        let correction = d.clock_correction_ns();
        deadline = (deadline + period).saturating_add_signed(if follow { correction } else { 0 });
        if tick == ticks / 2 {
            missed_at_half = drives(&d)[0].1;
        }
    }
    let missed = drives(&d)[0].1 - missed_at_half;
    let phase = d.distributed_clocks().expect("on distributed clocks").after_sync0_ns;
    (missed, phase, (1e9 / p.cycle_hz()) as u64)
}

#[test]
fn the_motor_loop_follows_the_bus_clock() {
    let (missed, phase, cycle) = run_on_a_drifting_bus(true);
    eprintln!("following: {missed} missed, phase {phase} of {cycle}");
    assert_eq!(missed, 0, "every SYNC0 had fresh outputs");
    // A quarter cycle after SYNC0, give or take the wake-up jitter.
    let error = phase.abs_diff(cycle / 4);
    assert!(error < 40_000, "frame {phase} ns after SYNC0, {error} ns from a quarter cycle");
    // Not following, the 50 ppm walk a whole cycle in 20 s and the frames
    // cross SYNC0: the drives latch a cycle without fresh outputs.
    let (missed, _, _) = run_on_a_drifting_bus(false);
    eprintln!("not following: {missed} missed");
    assert!(missed > 0, "a loop that ignores the bus's clock slides across SYNC0");
}
