//! `[plate]` and `[motion]` are read straight into `rt_core::PlateParams`
//! and `upm_motion::MotionParams`; these tests hold the file's side of
//! them.

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
        assert_eq!(params.motion.part_dynamics, upm_motion::PartDynamicsParams::default());
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
        assert_eq!(
            (params.motion.part_dynamics.steps, params.motion.part_dynamics.about),
            (2, LinearizeAbout::Rest)
        );
        assert_eq!((params.motion.part_dynamics.mu_g, params.motion.part_dynamics.substeps), (3.0, 8));
        // What a rig file does not set stays the model's default.
        let d = upm_motion::PartDynamicsParams::default();
        let p = params.motion.part_dynamics;
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
