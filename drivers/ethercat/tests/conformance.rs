//! The driver conformance suite for the EtherCAT driver over the simulated
//! chain: the same checks the simulator passes, through the whole
//! MainDevice stack (ethercrab, CiA 402, the chain, the servo model).

mod common;

use drivers::{BodyShape, PartSpec, SimConfig};
use ethercat_sim::SimulatedRig;
use upm_ethercat::{EthercatDriver, EthercatParams};
use upm_hardware::conformance;

fn ethercat(cycle_divisor: u32) -> EthercatDriver<SimulatedRig> {
    let parts =
        [PartSpec { shape: BodyShape::Point { radius: 0.01 }, mass: 0.04, position: [0.5, 0.0], angle: 0.0 }];
    let p = EthercatParams { cycle_divisor, ..common::params() };
    EthercatDriver::start(common::chain(&p, &parts), p, SimConfig::default().rig)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Bus cycles of 4 and 5 ticks (2.5 and 2 kHz), which divide the demo
/// motion's 160-tick cycle, so the home check reads the pose at a cycle's
/// end. The default, 3 ticks, does not divide it (the pose read would be
/// up to two ticks into the next cycle, the plate moving on); the whole
/// closed loop runs on it in clients/upm/tests/ethercat_rig.rs.
#[test]
fn ethercat_over_the_simulated_chain_conforms() {
    for cycle in [4, 5] {
        // Readings lag commands by two bus cycles: the target reaches the
        // drive's interpolator, which reaches it a cycle later, and the
        // position reported is latched as the next frame passes. Closed to
        // 15 µm (the demo motion swings ±0.6 mm in 16 ms; the drive
        // interpolates between targets).
        let t = conformance::Tolerances { settle: 400, home: 1.5e-5, latency_ticks: 2 * u64::from(cycle) };
        conformance::run_all_with(|| ethercat(cycle), t);
    }
}
