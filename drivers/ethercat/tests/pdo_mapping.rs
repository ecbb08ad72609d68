//! The driver writes its PDO mapping by SDO at start-up, whatever the
//! drives' defaults: drives that come up mapping only controlword/target
//! and statusword/position run with the full image (feed-forward and
//! torque) once started; a drive that cannot map an entry stops the start
//! with one line naming the drive and the object.

mod common;

use drivers::SimConfig;
use ethercat_sim::SimulatedRig;
use ethercat_sim::pdo_map::PdoMap;
use upm_ethercat::{EthercatDriver, StartError};
use upm_hardware::{ActuatorCommand, PlateDriver, PlateState};

const RX_ALL: [u32; 5] = [0x6040_0010, 0x607A_0020, 0x60B1_0020, 0x60B2_0010, 0x6060_0008];
const TX_ALL: [u32; 4] = [0x6041_0010, 0x6064_0020, 0x6077_0010, 0x6061_0008];

fn start(remap: impl Fn(usize) -> (PdoMap, PdoMap)) -> Result<EthercatDriver<SimulatedRig>, StartError> {
    let p = common::params();
    let mut rig = common::chain(&p, &[]);
    for (i, d) in rig.chain.devices.iter_mut().enumerate() {
        (d.drive.rx, d.drive.tx) = remap(i);
    }
    EthercatDriver::start(rig, p, SimConfig::default().rig)
}

#[test]
fn drives_with_a_minimal_default_mapping_are_remapped_at_start() {
    let minimal =
        |_| (PdoMap::new(0x1600, &RX_ALL[..2], &RX_ALL), PdoMap::new(0x1A00, &TX_ALL[..2], &TX_ALL));
    let mut d = start(minimal).unwrap_or_else(|e| panic!("{e}"));
    let mapped = d.with_wire(|w| {
        w.chain.devices.iter().map(|s| (s.drive.rx.bytes(), s.drive.tx.bytes())).collect::<Vec<_>>()
    });
    assert!(mapped.as_ref().is_some_and(|m| m.iter().all(|b| *b == (13, 9))), "{mapped:?}");
    // The feed-forward reaches the drive through the new image.
    let mut cmd = ActuatorCommand::HOME;
    cmd.position[0] = 1e-4;
    cmd.velocity[0] = 1e-3;
    for _ in 0..300 {
        assert!(d.write(&cmd).is_ok());
        d.advance();
    }
    assert!(d.read(&mut PlateState::default()).is_ok());
    let offset = d.with_wire(|w| w.chain.devices[0].drive.velocity_offset);
    assert_eq!(offset, Some(100_000), "1 mm/s at 1e8 counts/m");
}

#[test]
fn a_drive_that_cannot_map_an_entry_stops_the_start_naming_it() {
    // Drive 2 cannot map the torque offset (0x60B2).
    let without_torque = |i| {
        let rx: Vec<u32> = RX_ALL.iter().copied().filter(|e| i != 2 || *e != 0x60B2_0010).collect();
        (PdoMap::new(0x1600, &rx, &rx), PdoMap::new(0x1A00, &TX_ALL, &TX_ALL))
    };
    let e = start(without_torque).expect_err("refused");
    assert!(matches!(e, StartError::Sdo { position: 2, index: 0x1600, .. }), "{e:?}");
    let line = e.to_string();
    assert!(line.contains("0x1600") && line.contains('2'), "{line}");
}
