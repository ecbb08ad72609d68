//! What the EtherCAT driver's tests share: the driver's parameters for the
//! default simulator's rig, and the simulated chain of drives moving it.

use drivers::{PartSpec, SimConfig, Simulator};
use ethercat_sim::SimulatedRig;
use upm_ethercat::EthercatParams;

/// The driver's defaults for the default simulator's rig.
pub fn params() -> EthercatParams {
    let cfg = SimConfig::default();
    EthercatParams { tick_hz: cfg.tick_hz, count: cfg.rig.count, ..EthercatParams::default() }
}

/// The chain of drives moving the default simulator with `parts` on it.
pub fn chain(p: &EthercatParams, parts: &[PartSpec]) -> SimulatedRig {
    SimulatedRig::for_params(Simulator::new(SimConfig::default(), parts).expect("default sim"), p)
}
