//! `[driver]`: what moves the plate. The physics simulator (`"sim"`, the
//! default); CiA 402 drives over EtherCAT on a NIC (`"ethercat"`); or the
//! same EtherCAT driver over a simulated chain whose servos move the
//! physics simulator, in process (`"ethercat-sim"`). The bus's settings
//! are read straight into `upm_ethercat::EthercatParams`.

use core::fmt;

use serde::de::{MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
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

#[derive(Debug, Clone, Default, PartialEq)]
pub struct DriverSection {
    pub kind: DriverChoice,
    /// The NIC the EtherCAT bus hangs on (`kind = "ethercat"`).
    pub interface: String,
    /// The drives expected on the bus, in bus order, one per actuator;
    /// empty = UPM's simulated drive at every position.
    pub subdevices: Vec<ExpectedSubDevice>,
    /// The bus cycle, the drives' scaling and distributed clocks.
    pub bus: EthercatParams,
}

const OWN_KEYS: [&str; 3] = ["kind", "interface", "subdevices"];

impl<'de> Deserialize<'de> for DriverSection {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = DriverSection;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("the [driver] table")
            }
            fn visit_map<M: MapAccess<'de>>(self, m: M) -> Result<DriverSection, M::Error> {
                let mut own = DriverSection::default();
                own.bus = rig_config::shared_table::read_shared(m, &OWN_KEYS, |key, m| {
                    match key {
                        "kind" => own.kind = m.next_value()?,
                        "interface" => own.interface = m.next_value()?,
                        _ => own.subdevices = m.next_value()?,
                    }
                    Ok(())
                })?;
                Ok(own)
            }
        }
        d.deserialize_map(V)
    }
}

impl Serialize for DriverSection {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut table = rig_config::shared_table::write_rest(&self.bus)?;
        let value = |v: Result<toml::Value, toml::ser::Error>| v.map_err(serde::ser::Error::custom);
        table.insert("kind".into(), value(toml::Value::try_from(self.kind))?);
        table.insert("interface".into(), self.interface.clone().into());
        table.insert("subdevices".into(), value(toml::Value::try_from(&self.subdevices))?);
        table.serialize(s)
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
            expected[..count].copy_from_slice(&self.subdevices);
        }
        let p = EthercatParams { expected, count, tick_hz, ..self.bus };
        p.validate().map_err(|e| e.to_string())?;
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use crate::config::CoreConfig;

    #[test]
    fn the_bus_settings_are_read_beside_kind_and_drives_and_errors_name_the_field() {
        let text = "[driver]\nkind = \"ethercat-sim\"\ncycle_divisor = 5\n\
                    [[driver.subdevices]]\nvendor = 1\nproduct = 2\n";
        let c: CoreConfig = CoreConfig::parse(text, "x.toml").expect("parses");
        assert_eq!((c.driver.bus.cycle_divisor, c.driver.subdevices.len()), (5, 1));
        let back: CoreConfig =
            CoreConfig::parse(&toml::to_string(&c).expect("prints"), "x.toml").expect("reads");
        assert_eq!(back.driver, c.driver);
        for (bad, field) in [
            ("[driver]\ncycle_divsor = 5", "driver.cycle_divsor: "),
            ("[driver]\nkind = \"can\"", "driver.kind: "),
            ("[driver]\ncycle_divisor = \"x\"", "cycle_divisor: invalid type"),
            ("[[driver.subdevices]]\nvendor = 1", "driver.subdevices[0]: "),
        ] {
            let e = CoreConfig::<toml::Table>::parse(bad, "x.toml").expect_err(bad).to_string();
            assert!(e.contains(field) && !e.contains('\n'), "{bad}: {e}");
        }
    }
}
