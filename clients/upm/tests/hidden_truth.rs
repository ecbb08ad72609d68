//! The plate's hidden truth (`[sim] truth`) reaches the simulator and
//! nothing else: the controller's crates cannot link it, and changing it
//! leaves the controller's configuration and its first inputs unchanged.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use upm_cli::config::truth::TruthSection;
use upm_cli::scenario::{Scenario, resolve};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn toml_at(path: &Path) -> toml::Table {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse().unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Each workspace package's normal (not dev) dependencies on other
/// workspace packages.
fn workspace_graph() -> BTreeMap<String, BTreeSet<String>> {
    let ws = toml_at(&root().join("Cargo.toml"));
    let members: Vec<String> = ws["workspace"]["members"]
        .as_array()
        .expect("members")
        .iter()
        .map(|m| m.as_str().expect("member").to_owned())
        .collect();
    let mut packages = BTreeMap::new();
    for m in &members {
        let t = toml_at(&root().join(m).join("Cargo.toml"));
        let name = t["package"]["name"].as_str().expect("name").to_owned();
        let deps: BTreeSet<String> = t
            .get("dependencies")
            .and_then(|d| d.as_table())
            .map(|d| d.keys().cloned().collect())
            .unwrap_or_default();
        packages.insert(name, deps);
    }
    let names: BTreeSet<String> = packages.keys().cloned().collect();
    packages.into_iter().map(|(n, d)| (n, d.intersection(&names).cloned().collect())).collect()
}

fn reaches(graph: &BTreeMap<String, BTreeSet<String>>, from: &str, to: &str) -> bool {
    let mut stack = vec![from.to_owned()];
    let mut seen = BTreeSet::new();
    while let Some(p) = stack.pop() {
        if p == to {
            return true;
        }
        if seen.insert(p.clone()) {
            stack.extend(graph.get(&p).into_iter().flatten().cloned());
        }
    }
    false
}

#[test]
fn the_controllers_crates_cannot_reach_the_simulator() {
    let graph = workspace_graph();
    assert!(reaches(&graph, "upm-cli", "drivers"), "the check must see the launcher link the simulator");
    for controller in ["rt-core", "ipc-types", "upm-rig-config", "upm-vision", "upm-planner", "upm-calibrate"]
    {
        assert!(graph.contains_key(controller), "{controller} is not a workspace package");
        assert!(
            !reaches(&graph, controller, "drivers"),
            "{controller} can reach the simulator and its truth"
        );
    }
}

#[test]
fn changing_the_truth_changes_the_plate_and_nothing_the_controller_sees() {
    for name in ["sort", "track"] {
        let sc = Scenario::load(&resolve(name)).expect("scenario");
        let base = sc.config(1, "truth").expect("config");
        for truth in ["worn", "random:3", "random:4"] {
            let mut c = base.clone();
            c.sim.truth = TruthSection::Preset(truth.into());
            c.validate("scenario").expect("valid");
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
