//! The driver `[driver]` names, built for the core process and for
//! lock-step runs, and the physics simulator behind it when there is one
//! (the truth camera and the rendered camera read its parts). Any
//! [`CoreConfig`] will do, whatever it makes of the clients' sections.

use anyhow::Context;
use drivers::Simulator;
use drivers::feed::FeedCell;
use ethercat_sim::serve::{ChainServer, ServerPlacement};
use ethercat_sim::veth::VethPair;
use ethercat_sim::{ChainTime, SimulatedRig};
use upm_ethercat::EthercatDriver;
use upm_hardware::PlateDriver;

use crate::config::{CoreConfig, SimParts};

/// A driver whose plate is the physics simulator's.
pub trait SimulatedPlant: PlateDriver + Send + 'static {
    /// Run `f` on the simulator (no allocation: a lock-step loop's view).
    fn with_simulator(&self, f: &mut dyn FnMut(&Simulator));
    /// The simulator, wherever it steps, publishes its ground truth every
    /// `every` ticks from now on (start-up; see
    /// [`Simulator::publish_ground_truth`]); None if the simulator cannot
    /// be reached.
    fn publish_ground_truth(
        &mut self,
        every: u64,
        templates: Vec<ipc_types::PartState>,
    ) -> Option<triple_buffer::Output<ipc_types::PartStates>>;
    /// Have the feed cell write its status every `every_ms` (see
    /// [`FeedCell::publish_status`]); None without a cell.
    fn publish_feed_status(&mut self, every_ms: u64) -> Option<triple_buffer::Output<ipc_types::FeedStatus>>;
    /// The feed cell's mailbox for an external robot's picks (see
    /// [`FeedCell::accept_picks`]); None without one.
    fn accept_picks(&mut self) -> Option<std::sync::Arc<drivers::feed::PickMailbox>>;
    /// The feed cell's mailbox for changeovers (see
    /// [`FeedCell::accept_recipes`]); None without a cell.
    fn accept_recipes(&mut self) -> Option<drivers::feed::RecipeMailbox>;
}

impl SimulatedPlant for Simulator {
    fn with_simulator(&self, f: &mut dyn FnMut(&Simulator)) {
        f(self)
    }
    fn publish_ground_truth(
        &mut self,
        every: u64,
        templates: Vec<ipc_types::PartState>,
    ) -> Option<triple_buffer::Output<ipc_types::PartStates>> {
        Some(Simulator::publish_ground_truth(self, every, templates))
    }
    fn publish_feed_status(&mut self, every_ms: u64) -> Option<triple_buffer::Output<ipc_types::FeedStatus>> {
        FeedCell::publish_status(self, every_ms)
    }
    fn accept_picks(&mut self) -> Option<std::sync::Arc<drivers::feed::PickMailbox>> {
        FeedCell::accept_picks(self)
    }
    fn accept_recipes(&mut self) -> Option<drivers::feed::RecipeMailbox> {
        FeedCell::accept_recipes(self)
    }
}

impl SimulatedPlant for EthercatDriver<SimulatedRig> {
    fn with_simulator(&self, f: &mut dyn FnMut(&Simulator)) {
        // The wire is only ever in use during an exchange on this thread.
        let _ = self.with_wire(|w| f(&w.sim));
    }
    fn publish_ground_truth(
        &mut self,
        every: u64,
        templates: Vec<ipc_types::PartState>,
    ) -> Option<triple_buffer::Output<ipc_types::PartStates>> {
        // Start-up: no exchange is under way, so the wire is free.
        self.with_wire(|w| w.sim.publish_ground_truth(every, templates))
    }
    fn publish_feed_status(&mut self, every_ms: u64) -> Option<triple_buffer::Output<ipc_types::FeedStatus>> {
        self.with_wire(|w| FeedCell::publish_status(&mut w.sim, every_ms)).flatten()
    }
    fn accept_picks(&mut self) -> Option<std::sync::Arc<drivers::feed::PickMailbox>> {
        self.with_wire(|w| FeedCell::accept_picks(&mut w.sim)).flatten()
    }
    fn accept_recipes(&mut self) -> Option<drivers::feed::RecipeMailbox> {
        self.with_wire(|w| FeedCell::accept_recipes(&mut w.sim)).flatten()
    }
}

/// The physics simulator with `[sim]`'s parts.
pub fn simulator<V, P, C>(
    config: &CoreConfig<V, P, C>,
    shown: &str,
) -> anyhow::Result<(Simulator, SimParts)> {
    if let Some(recipe) = config.feed_recipe(shown)? {
        let sim = drivers::feed::FeedCell::simulator(
            config.sim_config(shown)?,
            &recipe,
            config.part_mass(),
            config.feed.robot,
        )
        .map_err(|e| anyhow::anyhow!("feed cell: {e}"))?;
        let parts = SimParts::of_pool(&sim);
        return Ok((sim, parts));
    }
    let parts = config.sim_parts(shown)?;
    let mut sim = Simulator::new(config.sim_config(shown)?, &parts.specs)
        .map_err(|e| anyhow::anyhow!("simulator: {e}"))?;
    for (i, &scale) in parts.friction.iter().enumerate() {
        // In range by construction (`SimSection::parts` checked each class).
        anyhow::ensure!(sim.set_part_friction(i, scale), "sim.parts[{i}]: friction scale {scale} refused");
    }
    Ok((sim, parts))
}

/// The EtherCAT driver over a simulated chain whose servos move the
/// simulator (started: the bus is in OP and every drive enabled).
pub fn ethercat_sim<V, P, C>(
    config: &CoreConfig<V, P, C>,
    shown: &str,
) -> anyhow::Result<(EthercatDriver<SimulatedRig>, SimParts)> {
    ethercat_sim_with(config, shown, |_| {})
}

/// [`ethercat_sim`], the chain prepared by `prepare` before start-up (so
/// that its clocks are what the bus starts with).
pub fn ethercat_sim_with<V, P, C>(
    config: &CoreConfig<V, P, C>,
    shown: &str,
    prepare: impl FnOnce(&mut SimulatedRig),
) -> anyhow::Result<(EthercatDriver<SimulatedRig>, SimParts)> {
    let (mut chain, p, rig, parts) = simulated_chain(config, shown)?;
    prepare(&mut chain);
    let driver = EthercatDriver::start(chain, p, rig)
        .map_err(anyhow::Error::msg)
        .context("driver.kind = \"ethercat-sim\"")?;
    Ok((driver, parts))
}

/// The simulated chain `[driver]` and `[sim]` describe, the driver's
/// parameters and the rig's.
fn simulated_chain<V, P, C>(
    config: &CoreConfig<V, P, C>,
    shown: &str,
) -> anyhow::Result<(SimulatedRig, upm_ethercat::EthercatParams, upm_motion::RigParams, SimParts)> {
    let (sim, parts) = simulator(config, shown)?;
    let p = config.ethercat_params(shown)?;
    let rig = *sim.rig().params();
    Ok((SimulatedRig::for_params(sim, &p), p, rig, parts))
}

/// For real runs: the simulated chain keeps real time (CLOCK_MONOTONIC)
/// and the reference drive's crystal runs 30 ppm fast, a typical part, so
/// the motor loop must follow the bus's clock as on a real rig. Lock-step
/// runs keep the plant's time (deterministic).
pub fn keep_real_time(rig: &mut SimulatedRig) {
    rig.chain_time = ChainTime::Source(Box::new(ipc_types::monotonic_now_ns));
    if let Some(reference) = rig.chain.devices.first_mut() {
        reference.drift_ppb = 30_000;
    }
}

/// The EtherCAT driver on `driver.interface` (needs CAP_NET_RAW).
pub fn ethercat<V, P, C>(
    config: &CoreConfig<V, P, C>,
    shown: &str,
) -> anyhow::Result<EthercatDriver<upm_ethercat::RawSocketWire>> {
    let p = config.ethercat_params(shown)?;
    let wire = upm_ethercat::RawSocketWire::open(&config.driver.interface, p.frame_deadline())
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("driver.interface {:?}", config.driver.interface))?;
    let rig = config.core_params(shown)?.rig;
    EthercatDriver::start(wire, p, rig).map_err(anyhow::Error::msg).context("driver.kind = \"ethercat\"")
}

/// The EtherCAT driver talking over a veth pair to the simulated chain on
/// its far end (a network namespace of its own, served by a thread of
/// this process): frames cross the kernel's network stack as they would
/// to a NIC. Dropping it stops the chain and deletes the pair.
#[derive(Debug)]
pub struct EthercatOverVeth {
    driver: EthercatDriver<upm_ethercat::RawSocketWire>,
    chain: ChainServer<SimulatedRig>,
}

impl EthercatOverVeth {
    /// The MainDevice's end of the pair.
    pub fn interface(&self) -> &str {
        self.chain.near()
    }

    /// The simulated chain, to read what its drives saw after a run.
    pub fn chain(&self) -> std::sync::Arc<std::sync::Mutex<SimulatedRig>> {
        self.chain.wire.clone()
    }
}

impl PlateDriver for EthercatOverVeth {
    fn limits(&self) -> upm_hardware::ActuatorLimits {
        self.driver.limits()
    }
    fn tick_period(&self) -> f64 {
        self.driver.tick_period()
    }
    fn read(&mut self, state: &mut upm_hardware::PlateState) -> Result<(), upm_hardware::ReadError> {
        self.driver.read(state)
    }
    fn write(&mut self, command: &upm_hardware::ActuatorCommand) -> Result<(), upm_hardware::WriteError> {
        self.driver.write(command)
    }
    fn hold(&mut self) {
        self.driver.hold();
    }
    fn advance(&mut self) {
        self.driver.advance();
    }
    fn clock_correction_ns(&mut self) -> i64 {
        self.driver.clock_correction_ns()
    }
    fn health(&self) -> upm_hardware::DriverHealth {
        self.driver.health()
    }
}

impl SimulatedPlant for EthercatOverVeth {
    fn with_simulator(&self, f: &mut dyn FnMut(&Simulator)) {
        // The chain's thread (SCHED_FIFO, just below the motor, on its CPU)
        // holds the lock only while it answers a frame.
        if let Ok(rig) = self.chain.wire.lock() {
            f(&rig.sim);
        }
    }
    fn publish_ground_truth(
        &mut self,
        every: u64,
        templates: Vec<ipc_types::PartState>,
    ) -> Option<triple_buffer::Output<ipc_types::PartStates>> {
        // The chain's thread steps the simulator and so writes the truth.
        let mut rig = self.chain.wire.lock().ok()?;
        Some(rig.sim.publish_ground_truth(every, templates))
    }
    fn publish_feed_status(&mut self, every_ms: u64) -> Option<triple_buffer::Output<ipc_types::FeedStatus>> {
        let mut rig = self.chain.wire.lock().ok()?;
        FeedCell::publish_status(&mut rig.sim, every_ms)
    }
    fn accept_picks(&mut self) -> Option<std::sync::Arc<drivers::feed::PickMailbox>> {
        let mut rig = self.chain.wire.lock().ok()?;
        FeedCell::accept_picks(&mut rig.sim)
    }
    fn accept_recipes(&mut self) -> Option<drivers::feed::RecipeMailbox> {
        let mut rig = self.chain.wire.lock().ok()?;
        FeedCell::accept_recipes(&mut rig.sim)
    }
}

/// `ethercat-sim` over a veth pair, when this process may create one
/// (root); `Ok(Err(why))` when it may not, so the caller can fall back to
/// the in-process chain and say why.
pub fn ethercat_over_veth<V, P, C>(
    config: &CoreConfig<V, P, C>,
    shown: &str,
) -> anyhow::Result<Result<(EthercatOverVeth, SimParts), String>> {
    let pair = match VethPair::create(&format!("c{}", std::process::id() % 10_000_000)) {
        Ok(pair) => pair,
        Err(why) => return Ok(Err(why)),
    };
    let (mut chain, p, rig, parts) = simulated_chain(config, shown)?;
    let core = config.core_params(shown)?;
    keep_real_time(&mut chain);
    let placement = ServerPlacement {
        realtime: Some((core.rt.motor_priority.saturating_sub(1).max(1), core.rt.motor_cpu.unwrap_or(0))),
    };
    let chain = ChainServer::start(pair, chain, placement)
        .map_err(anyhow::Error::msg)
        .context("driver.kind = \"ethercat-sim\": the simulated chain on the veth pair")?;
    let wire = upm_ethercat::RawSocketWire::open(chain.near(), p.frame_deadline())
        .map_err(anyhow::Error::msg)
        .with_context(|| format!("driver.kind = \"ethercat-sim\": {}", chain.near()))?;
    let driver = EthercatDriver::start(wire, p, rig)
        .map_err(anyhow::Error::msg)
        .context("driver.kind = \"ethercat-sim\" over veth")?;
    Ok(Ok((EthercatOverVeth { driver, chain }, parts)))
}
