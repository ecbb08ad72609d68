//! The plate's hidden truth (`[sim] truth`) reaches the simulator and
//! nothing else: changing it leaves the controller's configuration and its
//! first inputs unchanged (that the controller's crates cannot link the
//! simulator is `tests/tests/dependency_table.rs`).

use upm_commands::config::truth::TruthSection;
use upm_commands::scenario::{Scenario, resolve};

#[test]
fn changing_the_truth_changes_the_plate_and_nothing_the_controller_sees() {
    for name in ["sort", "track"] {
        let sc = Scenario::load(&resolve(name)).expect("scenario");
        let base = sc.config(1, "truth").expect("config");
        for truth in ["worn", "random:3", "random:4"] {
            let mut c = base.clone();
            c.sim.truth = TruthSection::Preset(truth.into());
            upm_commands::config::validate(&c, "scenario").expect("valid");
            // The simulator changes…
            assert_ne!(c.sim_config("s").expect("sim"), base.sim_config("s").expect("sim"), "{name} {truth}");
            // …the core's parameters, the planner's, vision's and the
            // camera's sections do not, nor where the parts start.
            assert_eq!(
                c.core_params("s").expect("core"),
                base.core_params("s").expect("core"),
                "{name} {truth}"
            );
            assert_eq!(c.planner, base.planner);
            assert_eq!(c.vision, base.vision);
            assert_eq!(c.camera, base.camera);
            let (p, q) = (c.sim_parts("s").expect("parts"), base.sim_parts("s").expect("parts"));
            assert_eq!((p.specs, p.ids, p.classes), (q.specs, q.ids, q.classes), "{name} {truth}");
        }
    }
}
