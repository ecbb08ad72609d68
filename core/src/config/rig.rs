//! `[plate]` and `[motion]`: the rig itself, shared by the core and the
//! simulator.

use rt_core::CoreParams;
use serde::{Deserialize, Serialize};
use upm_motion::PartDynamicsParams;
use upm_motion::{MotionLimits, MotionParams};

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct PlateSection {
    pub half_extent: [f64; 2],
    pub mu_m_g: f64,
    pub centers: Vec<[f64; 2]>,
}

#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct MotionSection {
    pub tick_hz: f64,
    pub slot_ticks: u32,
    pub displacement_mm: f64,
    pub k_max: f64,
    /// 0: one slot per center (the paper); N: centers are candidates, N
    /// slots per cycle.
    pub cycle_slots: usize,
    /// true: the solver integrates each part's outline (disc, polygon) as
    /// vision reports it; false: every part is a point (the paper).
    pub part_shapes: bool,
    /// The core's correction for each part's own velocity and spin.
    pub part_dynamics: PartDynamicsParams,
    /// The motor scales its feed-forward to the plate's mass and inertia
    /// as the drives' servo effort shows them; false: the model's. Unset:
    /// on with the simulator's drives (whose servo is specified in
    /// `[sim]`), off with EtherCAT's (which exchange forces only every
    /// `cycle_divisor` ticks; asking for it there is an error).
    pub adapt_plate_inertia: Option<bool>,
    pub max_angle: f64,
    pub max_angular_velocity: f64,
    pub max_angular_acceleration: f64,
    pub max_point_speed: f64,
    pub max_point_acceleration: f64,
}

impl Default for PlateSection {
    fn default() -> Self {
        let c = CoreParams::default();
        Self { half_extent: c.motion.plate_half_extent, mu_m_g: c.mu_m_g, centers: c.centers }
    }
}

impl Default for MotionSection {
    fn default() -> Self {
        let m = MotionParams::default();
        Self {
            tick_hz: m.tick_hz,
            slot_ticks: m.slot_ticks,
            displacement_mm: m.displacement * 1e3,
            k_max: m.k_max,
            cycle_slots: 0,
            part_shapes: true,
            part_dynamics: PartDynamicsParams::default(),
            adapt_plate_inertia: None,
            max_angle: m.limits.max_angle,
            max_angular_velocity: m.limits.max_angular_velocity,
            max_angular_acceleration: m.limits.max_angular_acceleration,
            max_point_speed: m.limits.max_point_speed,
            max_point_acceleration: m.limits.max_point_acceleration,
        }
    }
}

impl MotionSection {
    /// The motion parameters of `plate`; checked with the rest of the core's.
    pub fn params(&self, plate: &PlateSection) -> MotionParams {
        MotionParams {
            tick_hz: self.tick_hz,
            slot_ticks: self.slot_ticks,
            displacement: self.displacement_mm * 1e-3,
            plate_half_extent: plate.half_extent,
            k_max: self.k_max,
            limits: MotionLimits {
                max_angle: self.max_angle,
                max_angular_velocity: self.max_angular_velocity,
                max_angular_acceleration: self.max_angular_acceleration,
                max_point_speed: self.max_point_speed,
                max_point_acceleration: self.max_point_acceleration,
            },
            ..MotionParams::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::config::{ConfigError, CoreConfig};
    use upm_motion::LinearizeAbout;

    fn parse(text: &str) -> Result<CoreConfig, ConfigError> {
        CoreConfig::parse(text, "x.toml")
    }

    #[test]
    fn part_dynamics_left_out_is_the_default() {
        let params = parse("").expect("parses").core_params("x.toml").expect("valid");
        assert_eq!(params.part_dynamics, upm_motion::PartDynamicsParams::default());
        let e = parse(
            "[motion.part_dynamics]
max_work = 3
",
        )
        .expect_err("not a rig file key");
        assert!(e.to_string().contains("max_work"), "{e}");
    }

    #[test]
    fn part_dynamics_is_read_and_its_errors_name_the_field() {
        let text = "[motion.part_dynamics]\nsteps = 2\nabout = \"rest\"\nmu_g = 3.0\nsubsteps = 8\n";
        let params = parse(text).expect("parses").core_params("x.toml").expect("valid");
        assert_eq!((params.part_dynamics.steps, params.part_dynamics.about), (2, LinearizeAbout::Rest));
        assert_eq!((params.part_dynamics.mu_g, params.part_dynamics.substeps), (3.0, 8));
        // What a rig file does not set stays the model's default.
        let d = upm_motion::PartDynamicsParams::default();
        let p = params.part_dynamics;
        assert_eq!((p.follow, p.patch_forces, p.max_work), (d.follow, d.patch_forces, d.max_work));
        for (bad, field) in [
            ("steps = 9", "motion.part_dynamics.steps"),
            ("steps = 1\nmu_g = -1.0", "motion.part_dynamics.mu_g"),
            ("steps = 1\nsubsteps = 0", "motion.part_dynamics.substeps"),
        ] {
            let text = format!("[motion.part_dynamics]\n{bad}\n");
            let e = parse(&text).expect("parses").core_params("x.toml").expect_err(bad);
            let e = e.to_string();
            assert!(e.contains(field) && !e.contains('\n'), "{bad}: {e}");
        }
        let e = parse("[motion.part_dynamics]\nabout = \"later\"\n").expect_err("unknown");
        assert!(e.to_string().contains("about"), "{e}");
    }

    #[test]
    fn plate_inertia_adaptation_is_on_unless_the_file_turns_it_off() {
        let on = parse("").expect("parses").core_params("x.toml").expect("valid");
        assert_eq!(on.inertia_adaptation, Some(upm_motion::InertiaParams::default()));
        let text = "[motion]\nadapt_plate_inertia = false\n";
        let off = parse(text).expect("parses").core_params("x.toml").expect("valid");
        assert_eq!(off.inertia_adaptation, None);
        // EtherCAT's drives: off unless asked, and asking is refused.
        let bus = "[driver]\nkind = \"ethercat-sim\"\n";
        let off = parse(bus).expect("parses").core_params("x.toml").expect("valid");
        assert_eq!(off.inertia_adaptation, None);
        let asked = format!("{bus}[motion]\nadapt_plate_inertia = true\n");
        let e = parse(&asked).expect("parses").core_params("x.toml").expect_err("bus");
        assert!(e.to_string().contains("motion.adapt_plate_inertia") && !e.to_string().contains('\n'), "{e}");
        let e = parse("[motion]\nadapt_plate_inertia = 1\n").expect_err("not a bool");
        assert!(e.to_string().contains("adapt_plate_inertia"), "{e}");
    }
}
