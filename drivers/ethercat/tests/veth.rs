//! The EtherCAT driver over a real network path: a veth pair whose far end
//! sits in its own network namespace, where the simulated chain answers
//! frames on a raw socket. Start-up reaches OP and enables the drives, the
//! plate follows a closed motion, and pulling the link (the chain stops
//! answering) holds with frames counted lost, then recovers when it
//! answers again. Needs root; skipped with the reason otherwise.

use std::sync::atomic::Ordering::Relaxed;
use std::time::Duration;

use drivers::conformance::demo_motion;
use drivers::playback::play;
use drivers::{PartSpec, Shape, SimConfig, Simulator};
use ethercat_sim::SimulatedRig;
use ethercat_sim::serve::{ChainServer, ServerPlacement};
use ethercat_sim::veth::VethPair;
use rt_core::driver::{BusState, PlateDriver, PlateState, ReadError};
use rt_core::motion::Rig;
use upm_ethercat::{EthercatDriver, EthercatParams, RawSocketWire};

#[test]
fn the_driver_runs_over_a_veth_pair_and_survives_the_link_going_down() {
    let pair = match VethPair::create(&format!("{}", std::process::id() % 100_000)) {
        Ok(p) => p,
        Err(why) => {
            eprintln!("SKIPPED: {why}");
            return;
        }
    };
    let cfg = SimConfig::default();
    let parts =
        [PartSpec { shape: Shape::Point { radius: 0.01 }, mass: 0.04, position: [0.5, 0.0], angle: 0.0 }];
    let p = EthercatParams { tick_hz: cfg.tick_hz, count: cfg.rig.count, ..EthercatParams::default() };
    let sim = Simulator::new(cfg, &parts).expect("sim");
    let rig = SimulatedRig::new(sim, p.counts_per_metre, p.rated_force_n, p.cycle_divisor);
    let server =
        ChainServer::start(pair, rig, ServerPlacement { realtime: None }).expect("the chain's server");
    // A generous deadline: the far end is a normal thread on a shared VM.
    let wire = RawSocketWire::open(server.near(), Duration::from_millis(20)).expect("near end");
    let mut d = EthercatDriver::start(wire, p, cfg.rig).unwrap_or_else(|e| panic!("{e}"));
    let motion = demo_motion();
    let plate = Rig::new(cfg.rig).expect("rig");
    let mut s = PlateState::default();
    for c in 0..5 {
        let _ = play(&mut d, &plate, &motion, c * motion.cycle_ticks(), motion.cycle_ticks(), &mut s);
    }
    let h = d.health();
    assert_eq!(h.state, BusState::Op, "{h:?}");
    assert!(s.pose.x.abs() < 1e-3, "the plate moved as commanded and came back");

    // The link goes down: every exchange lost, the driver reports a fault.
    server.mute.store(true, Relaxed);
    for _ in 0..10 * p.cycle_divisor {
        d.hold();
        d.advance();
    }
    assert_eq!(d.read(&mut s), Err(ReadError::Fault));
    let lost = d.health().lost_frames;
    assert!(lost >= 10, "lost frames counted: {lost}");
    server.mute.store(false, Relaxed);
    for _ in 0..20 * p.cycle_divisor {
        d.hold();
        d.advance();
    }
    assert_eq!(d.read(&mut s), Ok(()), "back once the link answers");
    assert_eq!(d.health().state, BusState::Op);
    let answered = server.counters.answered.load(Relaxed);
    server.stop().expect("the chain's server");
    assert!(answered > 1000, "frames answered over the veth pair: {answered}");
}
