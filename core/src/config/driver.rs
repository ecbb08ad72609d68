//! `[driver]`: what moves the plate. The physics simulator (`"sim"`, the
//! default); CiA 402 drives over EtherCAT on a NIC (`"ethercat"`); or the
//! same EtherCAT driver over a simulated chain whose servos move the
//! physics simulator, in process (`"ethercat-sim"`).

use serde::{Deserialize, Serialize};
use upm_ethercat::{EthercatParams, ExpectedSubDevice};
use upm_hardware::MAX_ACTUATORS;

#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum DriverChoice {
    #[default]
    Sim,
    EthercatSim,
    Ethercat,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct DriverSection {
    pub kind: DriverChoice,
    /// The NIC the EtherCAT bus hangs on (`kind = "ethercat"`).
    pub interface: String,
    /// One EtherCAT cycle every this many motor ticks (1–4 kHz).
    pub cycle_divisor: u32,
    pub counts_per_metre: f64,
    pub following_error_m: f64,
    pub rated_force_n: f64,
    /// SYNC0 at the bus cycle when every drive offers distributed clocks.
    pub distributed_clocks: bool,
    /// The drives expected on the bus, in bus order, one per actuator;
    /// empty = UPM's simulated drive at every position.
    pub subdevices: Vec<SubDeviceSection>,
}

/// One `[[driver.subdevices]]` entry: identity from the drive's SII.
#[derive(Debug, Clone, Copy, Deserialize, Serialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct SubDeviceSection {
    pub vendor: u32,
    pub product: u32,
}

impl Default for DriverSection {
    fn default() -> Self {
        let p = EthercatParams::default();
        Self {
            kind: DriverChoice::Sim,
            interface: String::new(),
            cycle_divisor: p.cycle_divisor,
            counts_per_metre: p.counts_per_metre,
            following_error_m: p.following_error_m,
            rated_force_n: p.rated_force_n,
            distributed_clocks: p.distributed_clocks,
            subdevices: Vec::new(),
        }
    }
}

impl DriverSection {
    /// The EtherCAT driver's parameters for a rig of `count` actuators
    /// ticking at `tick_hz`; the message names the field.
    pub fn ethercat_params(&self, tick_hz: f64, count: usize) -> Result<EthercatParams, String> {
        if self.kind == DriverChoice::Ethercat && self.interface.is_empty() {
            return Err("driver.interface: kind = \"ethercat\" needs the NIC the bus hangs on".into());
        }
        let mut expected = [ExpectedSubDevice::SIMULATED_DRIVE; MAX_ACTUATORS];
        if !self.subdevices.is_empty() {
            if self.subdevices.len() != count {
                return Err(format!(
                    "driver.subdevices: {} listed, but the rig has {count} actuators (one drive each)",
                    self.subdevices.len()
                ));
            }
            for (e, s) in expected.iter_mut().zip(&self.subdevices) {
                *e = ExpectedSubDevice { vendor: s.vendor, product: s.product };
            }
        }
        let p = EthercatParams {
            expected,
            count,
            tick_hz,
            cycle_divisor: self.cycle_divisor,
            counts_per_metre: self.counts_per_metre,
            following_error_m: self.following_error_m,
            rated_force_n: self.rated_force_n,
            distributed_clocks: self.distributed_clocks,
            ..EthercatParams::default()
        };
        p.validate().map_err(|e| e.to_string())?;
        Ok(p)
    }
}
