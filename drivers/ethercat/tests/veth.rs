//! The EtherCAT driver over a real network path: a veth pair whose far end
//! sits in its own network namespace, where the simulated chain answers
//! frames on a raw socket. Start-up reaches OP and enables the drives, the
//! plate follows a closed motion, and pulling the link (the chain stops
//! answering) or taking the interface down holds with frames counted
//! lost, then recovers when it answers again. Needs root; skipped with
//! the reason otherwise.

mod common;

use std::sync::atomic::Ordering::Relaxed;
use std::time::Duration;

use drivers::{BodyShape, PartSpec, SimConfig};
use ethercat_sim::serve::{ChainServer, ServerPlacement};
use ethercat_sim::veth::VethPair;
use upm_ethercat::{EthercatDriver, RawSocketWire};
use upm_hardware::conformance::demo_motion;
use upm_hardware::playback::play;
use upm_hardware::{BusState, PlateDriver, PlateState, ReadError};
use upm_motion::Rig;

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
        [PartSpec { shape: BodyShape::Point { radius: 0.01 }, mass: 0.04, position: [0.5, 0.0], angle: 0.0 }];
    let p = common::params();
    let rig = common::chain(&p, &parts);
    let server =
        ChainServer::start(pair, rig, ServerPlacement { realtime: None }).expect("the chain's server");
    // A generous deadline: the far end is a normal thread on a shared VM.
    let wire = RawSocketWire::open(server.near(), Duration::from_millis(20)).expect("near end");
    let mut d = EthercatDriver::start(wire, p, cfg.rig).unwrap_or_else(|e| panic!("{e}"));
    let motion = demo_motion();
    let plate = Rig::new(cfg.rig).expect("rig");
    let mut s = PlateState::default();
    // Half a slot out (the demo motion swings ±0.6 mm; each of its four
    // slots comes home), then whole cycles home; the readings lag the
    // commands by two bus cycles.
    let n = motion.cycle_ticks();
    let lag = 2 * u64::from(p.cycle_divisor);
    let _ = play(&mut d, &plate, &motion, 0, n / 8 + lag, &mut s);
    let out = s.pose.x.abs().max(s.pose.y.abs());
    assert!(out > 1e-4, "the plate moved: {:?}", s.pose);
    let _ = play(&mut d, &plate, &motion, n / 8 + lag, n - n / 8, &mut s);
    for c in 1..4 {
        let _ = play(&mut d, &plate, &motion, c * n + lag, n, &mut s);
    }
    let h = d.health();
    assert_eq!(h.state, BusState::Op, "{h:?}");
    let off = s.pose.x.abs().max(s.pose.y.abs());
    assert!(off < out / 10.0, "the plate came back: {:?} after {out:e} out", s.pose);

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

    // The interface itself goes down (sends fail): held and counted, then
    // back when it comes up.
    let link = |state: &str| {
        let ok = std::process::Command::new("ip").args(["link", "set", server.near(), state]).status();
        assert!(ok.is_ok_and(|s| s.success()), "ip link set {state}");
    };
    link("down");
    let lost = d.health().lost_frames;
    for _ in 0..10 * p.cycle_divisor {
        d.hold();
        d.advance();
    }
    assert_eq!(d.read(&mut s), Err(ReadError::Fault), "link down");
    assert!(d.health().lost_frames >= lost + 10, "{:?}", d.health());
    link("up");
    // The carrier takes a moment to come back.
    let mut back = false;
    for _ in 0..2000 {
        d.hold();
        d.advance();
        if d.read(&mut s).is_ok() {
            back = true;
            break;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    assert!(back, "back once the link is up: {:?}", d.health());
    let answered = server.counters.answered.load(Relaxed);
    server.stop().expect("the chain's server");
    assert!(answered > 1000, "frames answered over the veth pair: {answered}");
}
