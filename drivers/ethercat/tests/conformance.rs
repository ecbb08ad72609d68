//! The driver conformance suite for the EtherCAT driver over the simulated
//! chain: the same checks the simulator passes, through the whole
//! MainDevice stack (ethercrab, CiA 402, the chain, the servo model).

use drivers::conformance;
use drivers::{PartSpec, Shape, SimConfig, Simulator};
use ethercat_sim::SimulatedRig;
use upm_ethercat::{EthercatDriver, EthercatParams};

fn ethercat() -> EthercatDriver<SimulatedRig> {
    let cfg = SimConfig::default();
    let parts =
        [PartSpec { shape: Shape::Point { radius: 0.01 }, mass: 0.04, position: [0.5, 0.0], angle: 0.0 }];
    let sim = Simulator::new(cfg, &parts).expect("default sim");
    let params = EthercatParams { tick_hz: cfg.tick_hz, count: cfg.rig.count, ..EthercatParams::default() };
    let rig = SimulatedRig::new(sim, params.counts_per_metre, params.rated_force_n, params.cycle_divisor);
    EthercatDriver::start(rig, params, cfg.rig).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn ethercat_over_the_simulated_chain_conforms() {
    // Readings lag commands by two bus cycles (5 ticks each): the target
    // reaches the drive's interpolator, which reaches it a cycle later,
    // and the position reported is latched as the next frame passes.
    let cycle = u64::from(EthercatParams::default().cycle_divisor);
    // Closed to 5 µm (the demo motion swings ±0.6 mm in 16 ms; the drive
    // interpolates between 0.5 ms targets).
    let t = conformance::Tolerances { settle: 400, home: 5e-6, latency_ticks: 2 * cycle };
    conformance::run_all_with(ethercat, t);
}
