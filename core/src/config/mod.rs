//! The rig's one TOML config, as the core reads it: every section and
//! field is optional and has a default; unknown fields are errors, and
//! every message names the field. `[plate]`, `[motion]`, `[rt]`,
//! `[safety]` and `[telemetry]` are read straight into the types the core
//! runs on (`rt_core::PlateParams`, `upm_motion::MotionParams`, …); one
//! module per remaining concern: [`core`] (the CPUs `[rt]` names), [`sim`]
//! (and its hidden [`truth`]), [`driver`]. The `[vision]`, `[planner]` and `[camera]`
//! sections belong to their crates: [`CoreConfig`] keeps them as written
//! (TOML tables) for the core, and `upm` reads the same schema with them
//! typed (`CoreConfig<VisionSection, PlannerConfig, CameraSection>`), so
//! the file's sections are declared once. Parsing has no side effects.

pub mod core;
pub mod driver;
pub mod feed;
pub mod rig;
pub mod sim;
pub mod truth;

use std::path::Path;

pub use rig_config::{ConfigError, ServiceSection};
use rt_core::{CoreParams, PlateParams, RtParams, SafetyParams, TelemetryParams};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use upm_motion::{MotionParams, RigParams};

pub use driver::{DriverChoice, DriverSection};
pub use feed::FeedSection;
pub use sim::{SimPartSection, SimParts, SimSection};

/// The rig file. `V`, `P` and `C` are the clients' sections (`[vision]`,
/// `[planner]`, `[camera]`): tables the core does not read, unless a
/// caller that links the clients' crates types them.
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct CoreConfig<V = toml::Table, P = toml::Table, C = toml::Table> {
    pub service: ServiceSection,
    pub plate: PlateParams,
    pub motion: MotionParams,
    pub rt: RtParams,
    pub safety: SafetyParams,
    pub telemetry: TelemetryParams,
    pub sim: SimSection,
    pub driver: DriverSection,
    /// The feed cell the simulator plays, if any.
    pub feed: FeedSection,
    pub vision: V,
    pub planner: P,
    pub camera: C,
    /// The plate calibration file core and planner load.
    pub calibration: rig_config::CalibrationSection,
}

impl<V, P, C> CoreConfig<V, P, C>
where
    Self: DeserializeOwned,
{
    /// Parse TOML text; errors name the field (`motion.tick_hz: invalid type …`).
    pub fn parse(text: &str, path: &str) -> Result<Self, ConfigError> {
        rig_config::parse_toml(text, path)
    }

    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        rig_config::load_toml(path)
    }
}

impl<P> CoreConfig<toml::Table, P, toml::Table> {
    /// The rate vision publishes PartStates at, as the clients will read
    /// it: the camera's `frame_hz` when vision reads camera frames, else
    /// vision's own.
    pub fn vision_frame_hz(&self) -> f64 {
        use rig_config::frame_rate::{DEFAULT_FRAME_HZ, publish_hz};
        let hz = |t: &toml::Table| {
            t.get("frame_hz")
                .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
                .unwrap_or(DEFAULT_FRAME_HZ)
        };
        let source = self.vision.get("source").and_then(toml::Value::as_str).unwrap_or_default();
        publish_hz(source, hz(&self.vision), hz(&self.camera))
    }
}

impl<V, P, C> CoreConfig<V, P, C> {
    /// The validated core parameters.
    pub fn core_params(&self, path: &str) -> Result<CoreParams, ConfigError> {
        self.core_params_inner().map_err(|message| ConfigError::invalid(path, message))
    }

    /// The motor's inertia estimate, for the drives as the rig specifies
    /// them: the simulator's. EtherCAT's report forces only every
    /// `cycle_divisor` ticks, not per command, so it stays off there.
    fn inertia_adaptation(&self) -> Result<Option<upm_motion::InertiaParams>, String> {
        let simulated = self.driver.kind == self::driver::DriverChoice::Sim;
        match (self.motion.adapt_plate_inertia, simulated) {
            (Some(false), _) | (None, false) => Ok(None),
            (Some(true) | None, true) => {
                Ok(Some(self.sim.config(self.motion.tick_hz, self.plate.half_extent)?.drive_servo()))
            }
            (Some(true), false) => Err(format!(
                "motion.adapt_plate_inertia: needs the simulator's drives, driver.kind is {:?}",
                self.driver.kind
            )),
        }
    }

    fn core_params_inner(&self) -> Result<CoreParams, String> {
        self.service.prefix_or(None)?;
        self::core::check_cpus(&self.rt)?;
        let rig = RigParams::default();
        let (twist_correction, part_friction) = match &self.calibration.file {
            Some(path) => {
                let c = rig_config::PlateCalibration::load(path)?;
                let identity = rig_config::plate_calibration::RigIdentity {
                    actuators: rig.count as u32,
                    centers: &self.plate.centers,
                    plate_half_extent: self.plate.half_extent,
                    mu_m_g: self.plate.mu_m_g,
                };
                c.check_rig(&identity).map_err(|e| format!("calibration.file {}: {e}", path.display()))?;
                let classes: Vec<(u32, f64)> = c.class_friction.iter().map(|f| (f.class, f.scale)).collect();
                let friction = upm_motion::PartFriction::new(&classes, c.friction_map, c.plate_half_extent)
                    .map_err(|e| format!("calibration.file {}: {e}", path.display()))?;
                (Some(c.twist_correction), friction)
            }
            None => (None, upm_motion::PartFriction::UNIFORM),
        };
        let params = CoreParams {
            plate: self.plate.clone(),
            motion: MotionParams { plate_half_extent: self.plate.half_extent, ..self.motion },
            rt: self.rt,
            safety: self.safety,
            telemetry: self.telemetry.clone(),
            rig,
            twist_correction,
            part_friction,
            inertia_adaptation: self.inertia_adaptation()?,
        };
        // Complete validation: the core would refuse an unplayable rig at start.
        params.playable_k_bounds().map_err(|e| e.to_string())?;
        Ok(params)
    }

    /// The simulator's configuration, consistent with the core's.
    pub fn sim_config(&self, path: &str) -> Result<drivers::SimConfig, ConfigError> {
        self.sim
            .config(self.motion.tick_hz, self.plate.half_extent)
            .map_err(|m| ConfigError::invalid(path, m))
    }

    /// The EtherCAT driver's parameters (for an EtherCAT `driver.kind`).
    pub fn ethercat_params(&self, path: &str) -> Result<upm_ethercat::EthercatParams, ConfigError> {
        let count = RigParams::default().count;
        self.driver.ethercat_params(self.motion.tick_hz, count).map_err(|m| ConfigError::invalid(path, m))
    }

    /// `[feed]`'s recipe, checked against `[plate]`; None without one.
    pub fn feed_recipe(&self, path: &str) -> Result<Option<upm_recipe::Recipe>, ConfigError> {
        let recipe = self.feed.recipe(self.plate.half_extent).map_err(|m| ConfigError::invalid(path, m))?;
        if recipe.is_some() && !self.sim.parts.is_empty() {
            let m = "sim.parts: a feed cell brings its own parts; leave [[sim.parts]] out";
            return Err(ConfigError::invalid(path, m));
        }
        Ok(recipe)
    }

    /// The mass of each simulated part (kg): μ·m·g over the simulator's μ·g.
    pub fn part_mass(&self) -> f64 {
        self.plate.mu_m_g / (self.sim.config.mu_kinetic * self.sim.config.gravity)
    }

    /// `[[sim.parts]]` as simulator part specs; ids must be unique.
    pub fn sim_parts(&self, path: &str) -> Result<SimParts, ConfigError> {
        self.sim.parts(self.plate.half_extent).map_err(|m| ConfigError::invalid(path, m))
    }

    /// The core's sections checked, as the core will check them at start
    /// (`upm` checks the clients' sections too).
    pub fn validate_core(&self, path: &str) -> Result<(), ConfigError> {
        self.core_params(path)?;
        self.sim_parts(path)?;
        self.sim_config(path)?;
        self.feed_recipe(path)?;
        if self.driver.kind != DriverChoice::Sim {
            self.ethercat_params(path)?;
        }
        Ok(())
    }

    /// The motor's CPU if normal-priority work should stay off it.
    pub fn cpu_to_avoid(&self) -> Option<usize> {
        self.rt.isolate_motor_cpu.then_some(self.rt.motor_cpu).flatten()
    }

    /// The motor thread's CPU, if it is pinned.
    pub fn rt_motor_cpu(&self) -> Option<usize> {
        self.rt.motor_cpu
    }

    pub fn histogram_dir(&self) -> Option<&Path> {
        (!self.telemetry.histogram_dir.is_empty()).then(|| Path::new(&self.telemetry.histogram_dir))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clients_sections_are_kept_as_written_and_others_are_refused() {
        let text = "[vision]\nframe_hz = \"not the core's\"\n[planner]\nname = \"sort\"\n";
        let c: CoreConfig = CoreConfig::parse(text, "x.toml").expect("the core does not read them");
        assert_eq!(c.vision["frame_hz"].as_str(), Some("not the core's"));
        assert_eq!(c.planner["name"].as_str(), Some("sort"));
        let e = CoreConfig::<toml::Table>::parse("[visio]\n", "x.toml").expect_err("unknown section");
        let e = e.to_string();
        assert!(e.starts_with("x.toml: visio: ") && e.contains("`vision`, `planner`, `camera`"), "{e}");
    }
}
