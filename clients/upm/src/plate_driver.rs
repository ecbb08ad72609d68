//! The driver `[driver]` names, built for the core process and for
//! lock-step runs, and the physics simulator behind it when there is one
//! (the truth camera and the rendered camera read its parts).

use anyhow::Context;
use drivers::Simulator;
use ethercat_sim::SimulatedRig;
use rt_core::driver::PlateDriver;
use upm_ethercat::EthercatDriver;

use crate::config::{Config, SimParts};

/// A driver whose plate is the physics simulator's.
pub trait SimulatedPlant: PlateDriver + Send + 'static {
    /// Run `f` on the simulator (on the motor thread: no allocation).
    fn with_simulator(&self, f: &mut dyn FnMut(&Simulator));
}

impl SimulatedPlant for Simulator {
    fn with_simulator(&self, f: &mut dyn FnMut(&Simulator)) {
        f(self)
    }
}

impl SimulatedPlant for EthercatDriver<SimulatedRig> {
    fn with_simulator(&self, f: &mut dyn FnMut(&Simulator)) {
        // The wire is only ever in use during an exchange on this thread.
        let _ = self.with_wire(|w| f(&w.sim));
    }
}

/// The physics simulator with `[sim]`'s parts.
pub fn simulator(config: &Config, shown: &str) -> anyhow::Result<(Simulator, SimParts)> {
    let parts = config.sim_parts(shown)?;
    let sim = Simulator::new(config.sim_config(shown)?, &parts.specs)
        .map_err(|e| anyhow::anyhow!("simulator: {e}"))?;
    Ok((sim, parts))
}

/// The EtherCAT driver over a simulated chain whose servos move the
/// simulator (started: the bus is in OP and every drive enabled).
pub fn ethercat_sim(
    config: &Config,
    shown: &str,
) -> anyhow::Result<(EthercatDriver<SimulatedRig>, SimParts)> {
    let (sim, parts) = simulator(config, shown)?;
    let p = config.ethercat_params(shown)?;
    let rig = *sim.rig().params();
    let chain = SimulatedRig::new(sim, p.counts_per_metre, p.rated_force_n, p.cycle_divisor);
    let driver = EthercatDriver::start(chain, p, rig)
        .map_err(anyhow::Error::msg)
        .context("driver.kind = \"ethercat-sim\"")?;
    Ok((driver, parts))
}

/// The EtherCAT driver on `driver.interface` (needs CAP_NET_RAW).
pub fn ethercat(config: &Config, shown: &str) -> anyhow::Result<EthercatDriver<upm_ethercat::RawSocketWire>> {
    let p = config.ethercat_params(shown)?;
    let deadline = std::time::Duration::from_secs_f64(0.5 / p.cycle_hz());
    let wire = upm_ethercat::RawSocketWire::open(&config.driver.interface, deadline)
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("driver.interface {:?}", config.driver.interface))?;
    let rig = config.core_params(shown)?.rig;
    EthercatDriver::start(wire, p, rig).map_err(anyhow::Error::msg).context("driver.kind = \"ethercat\"")
}
