//! Faults as the EtherCAT driver meets them, over the simulated chain: a
//! drive's fault, lost frames, a cut cable, and garbage from the wire.
//! Each makes `read` report a fault at the next exchange (so the core
//! holds), is counted, and clears without restarting anything. Start-up
//! refuses a bus that is not the one configured, naming the device.

mod common;

use common::params;
use drivers::{BodyShape, PartSpec, SimConfig};
use ethercat_sim::SimulatedRig;
use upm_ethercat::{EthercatDriver, EthercatParams, ExpectedSubDevice, StartError, Wire, WireError};
use upm_hardware::{ActuatorCommand, BusState, PlateDriver, PlateState, ReadError};

fn rig(params: &EthercatParams) -> SimulatedRig {
    let parts =
        [PartSpec { shape: BodyShape::Point { radius: 0.01 }, mass: 0.04, position: [0.5, 0.0], angle: 0.0 }];
    common::chain(params, &parts)
}

fn start<W: Wire>(wire: impl FnOnce(SimulatedRig) -> W) -> EthercatDriver<W> {
    let p = params();
    EthercatDriver::start(wire(rig(&p)), p, SimConfig::default().rig).unwrap_or_else(|e| panic!("{e}"))
}

/// Ticks of one bus cycle.
fn cycle() -> usize {
    params().cycle_divisor as usize
}

/// Hold for `ticks`, as the core does while the driver reports a fault;
/// the last read's outcome.
fn hold_for<W: Wire>(d: &mut EthercatDriver<W>, ticks: usize) -> Result<(), ReadError> {
    let mut s = PlateState::default();
    for _ in 0..ticks {
        d.hold();
        d.advance();
    }
    d.read(&mut s)
}

/// Move to a point off home and let it settle.
fn move_off<W: Wire>(d: &mut EthercatDriver<W>) {
    let mut cmd = ActuatorCommand::HOME;
    cmd.position[0] = 1e-3;
    cmd.position[1] = 1e-3;
    for _ in 0..400 {
        assert!(d.write(&cmd).is_ok());
        d.advance();
    }
    assert!(d.read(&mut PlateState::default()).is_ok());
}

#[test]
fn a_drive_fault_is_seen_at_the_next_exchange_and_reset_without_a_restart() {
    let mut d = start(|r| r);
    move_off(&mut d);
    assert!(d.with_wire(|w| w.chain.devices[1].drive.fault()).is_some());
    // The drive writes its inputs as a frame passes; the next frame reads
    // them: the fault is seen within two bus cycles.
    assert_eq!(hold_for(&mut d, 2 * cycle()), Err(ReadError::Fault), "fault seen within two bus cycles");
    let h = d.health();
    assert_eq!((h.state, h.faults[1], h.faults[0]), (BusState::Fault, 1, 0));
    // Fault reset, shutdown, switch on, enable: a few cycles.
    assert_eq!(hold_for(&mut d, 20 * cycle()), Ok(()), "drive back in operation enabled");
    assert_eq!(d.health().state, BusState::Op);
    assert_eq!(d.health().faults[1], 1, "one fault, counted once");
    // The hold brought the plate home.
    let mut s = PlateState::default();
    assert_eq!(hold_for(&mut d, 400), Ok(()));
    assert!(d.read(&mut s).is_ok());
    assert!(s.pose.x.abs() + s.pose.y.abs() < 1e-6, "home after hold: {:?}", s.pose);
}

#[test]
fn lost_frames_and_a_cut_cable_hold_and_are_counted_then_clear() {
    let mut d = start(|r| r);
    move_off(&mut d);
    assert!(d.with_wire(|w| w.chain.lose_frames(3)).is_some());
    assert_eq!(hold_for(&mut d, cycle()), Err(ReadError::Fault));
    assert_eq!(hold_for(&mut d, 2 * cycle()), Err(ReadError::Fault));
    assert_eq!(hold_for(&mut d, cycle()), Ok(()), "answers again");
    assert_eq!(d.health().lost_frames, 3);
    // Pull the cable after the second drive: short working counter.
    assert!(d.with_wire(|w| w.chain.cut_after(2)).is_some());
    assert_eq!(hold_for(&mut d, 10 * cycle()), Err(ReadError::Fault));
    assert_eq!(d.health().state, BusState::Fault);
    assert_eq!(d.health().lost_frames, 13);
    assert!(d.with_wire(|w| w.chain.cut_after(usize::MAX)).is_some());
    assert_eq!(hold_for(&mut d, cycle()), Ok(()), "mended");
    assert_eq!(d.health().state, BusState::Op);
    assert_eq!(d.health().faults, [0; 8], "no drive faulted: their targets held");
}

/// A wire that mangles answers, in turn, while `on`.
struct Mangler {
    rig: SimulatedRig,
    on: bool,
    n: u32,
}

impl Wire for Mangler {
    fn round_trip(&mut self, frame: &mut [u8]) -> Result<(), WireError> {
        let r = self.rig.round_trip(frame);
        if !self.on {
            return r;
        }
        self.n += 1;
        match self.n % 5 {
            // Wrong working counter on the process data (the LRW).
            0 => {
                if let Some(w) = lrw_working_counter(frame) {
                    *w = w.wrapping_add(1);
                }
            }
            // Not EtherCAT.
            1 => frame[12] = 0x08,
            // Garbage everywhere after the addresses.
            2 => frame[12..].iter_mut().enumerate().for_each(|(i, b)| *b = (i as u8).wrapping_mul(37)),
            // A frame length that disagrees with the datagrams.
            3 => frame[14] = 0xFF,
            // A failed receive.
            _ => return Err(WireError::Io(libc_eio())),
        }
        r
    }
}

/// The LRW datagram's working counter (low byte): datagrams start at 16,
/// each a 10-byte header (command first, length at 6), data, a 2-byte WKC.
fn lrw_working_counter(frame: &mut [u8]) -> Option<&mut u8> {
    const LRW: u8 = 12;
    let mut at = 16;
    loop {
        let flags = u16::from_le_bytes([*frame.get(at + 6)?, *frame.get(at + 7)?]);
        let wkc = at + 10 + usize::from(flags & 0x07FF);
        if frame[at] == LRW {
            return frame.get_mut(wkc);
        }
        if flags & 0x8000 == 0 {
            return None;
        }
        at = wkc + 2;
    }
}

fn libc_eio() -> i32 {
    5
}

#[test]
fn garbage_from_the_wire_is_counted_and_never_panics() {
    let mut d = start(|rig| Mangler { rig, on: false, n: 0 });
    move_off(&mut d);
    assert!(d.with_wire(|w| w.on = true).is_some());
    assert_eq!(hold_for(&mut d, 50 * cycle()), Err(ReadError::Fault));
    let (frames, lost, bad) = d.wire_counters();
    let h = d.health();
    assert_eq!(h.lost_frames, 50, "every exchange lost: {h:?}");
    assert!(bad >= 30 && lost >= 10, "frames {frames}, lost {lost}, bad {bad}");
    assert_eq!(h.bad_frames, bad);
    assert_eq!(d.unfinished_exchanges(), 0, "every exchange completed within its poll");
    assert!(d.with_wire(|w| w.on = false).is_some());
    assert_eq!(hold_for(&mut d, 20 * cycle()), Ok(()), "clean answers again");
    assert_eq!(d.health().state, BusState::Op);
}

#[test]
fn a_bus_that_is_not_the_one_configured_is_refused_naming_the_device() {
    let p = params();
    let mut short = rig(&p);
    short.chain.cut_after(3);
    let e = EthercatDriver::start(short, p, SimConfig::default().rig).err();
    assert_eq!(e, Some(StartError::Missing { position: 3, expected: ExpectedSubDevice::SIMULATED_DRIVE }));
    let line = e.map(|e| e.to_string()).unwrap_or_default();
    assert!(line.contains("subdevice 3") && line.contains("0x00000402") && !line.contains('\n'), "{line}");

    let mut other = p;
    other.expected[2] = ExpectedSubDevice { vendor: 0x2, product: 0x1234 };
    let e = EthercatDriver::start(rig(&p), other, SimConfig::default().rig).err();
    assert_eq!(e, Some(StartError::Unexpected { position: 2, vendor: 0x0055_504D, product: 0x402 }));

    let bad = EthercatParams { cycle_divisor: 1, ..p };
    let e = EthercatDriver::start(rig(&p), bad, SimConfig::default().rig).err().map(|e| e.to_string());
    assert!(e.is_some_and(|l| l.contains("driver.cycle_divisor")));
}
