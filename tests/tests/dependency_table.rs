//! Who may depend on whom (ARCHITECTURE.md §8), read from the Cargo
//! manifests, Cargo.lock and the table itself: every workspace crate has a
//! row, its workspace dependencies (normal, and its tests' own) are the
//! ones its row names; the controllers cannot reach the simulator; and the
//! RT core's binary links no client crate and none of the tools' heavy
//! crates (async runtimes, plots, images, reference solvers).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// What upm-core must not link, directly or through anything it links.
const NOT_IN_THE_CORE: [&str; 17] = [
    "tokio",
    "foxglove",
    "mcap",
    "plotters",
    "clarabel",
    "image",
    "indicatif",
    "tungstenite",
    "aprilgrid",
    "faer",
    "nalgebra",
    "upm-vision",
    "upm-planner",
    "upm-camera",
    "upm-recorder",
    "upm-calibrate",
    "upm-cli",
];

fn toml_at(path: &Path) -> toml::Table {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse().unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[derive(Debug, Default)]
struct Package {
    dir: String,
    /// Package names of its `[dependencies]` (renames resolved).
    normal: BTreeSet<String>,
    /// Of its `[dev-dependencies]` that are not also normal ones.
    dev_only: BTreeSet<String>,
}

/// The workspace's packages by name, from the manifests.
fn workspace() -> BTreeMap<String, Package> {
    let ws = toml_at(&Path::new(ROOT).join("Cargo.toml"));
    let ws = ws["workspace"].as_table().expect("[workspace]");
    let shared = ws["dependencies"].as_table().expect("[workspace.dependencies]");
    // A dependency's package: `package = "…"` here or in the workspace's entry.
    fn renamed(v: Option<&toml::Value>) -> Option<&str> {
        v?.get("package")?.as_str()
    }
    let package_of = |key: &str, value: &toml::Value| {
        renamed(Some(value)).or_else(|| renamed(shared.get(key))).unwrap_or(key).to_owned()
    };
    let deps = |t: &toml::Table, kind: &str| -> BTreeSet<String> {
        t.get(kind)
            .and_then(|d| d.as_table())
            .map(|d| d.iter().map(|(k, v)| package_of(k, v)).collect())
            .unwrap_or_default()
    };
    let mut packages = BTreeMap::new();
    for m in ws["members"].as_array().expect("members") {
        let dir = m.as_str().expect("member").to_owned();
        let t = toml_at(&Path::new(ROOT).join(&dir).join("Cargo.toml"));
        let name = t["package"]["name"].as_str().expect("name").to_owned();
        let normal = deps(&t, "dependencies");
        let dev_only = deps(&t, "dev-dependencies").difference(&normal).cloned().collect();
        packages.insert(name, Package { dir, normal, dev_only });
    }
    packages
}

/// Each package's dependencies on other workspace packages (normal only).
fn workspace_graph(packages: &BTreeMap<String, Package>) -> BTreeMap<String, BTreeSet<String>> {
    let names: BTreeSet<&String> = packages.keys().collect();
    packages
        .iter()
        .map(|(n, p)| (n.clone(), p.normal.iter().filter(|d| names.contains(d)).cloned().collect()))
        .collect()
}

fn reaches(graph: &BTreeMap<String, BTreeSet<String>>, from: &str, to: &str) -> bool {
    closure(graph, [from.to_owned()]).contains(to)
}

/// Everything reachable from `start` in `graph`, `start` included.
fn closure(
    graph: &BTreeMap<String, BTreeSet<String>>,
    start: impl IntoIterator<Item = String>,
) -> BTreeSet<String> {
    let mut stack: Vec<String> = start.into_iter().collect();
    let mut seen = BTreeSet::new();
    while let Some(p) = stack.pop() {
        if seen.insert(p.clone()) {
            stack.extend(graph.get(&p).into_iter().flatten().cloned());
        }
    }
    seen
}

/// Every crate `package` links, as far as the manifests and Cargo.lock
/// say: the workspace crates it reaches through normal dependencies, their
/// outside dependencies, and everything those list in Cargo.lock (every
/// version, feature and platform the lock knows: more than a build links,
/// never less).
fn links(packages: &BTreeMap<String, Package>, package: &str) -> BTreeSet<String> {
    let ours = closure(&workspace_graph(packages), [package.to_owned()]);
    let lock = toml_at(&Path::new(ROOT).join("Cargo.lock"));
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for p in lock["package"].as_array().expect("[[package]]") {
        let name = p["name"].as_str().expect("name").to_owned();
        // A workspace package's lock entry has its dev-dependencies too.
        if packages.contains_key(&name) {
            continue;
        }
        let deps = p.get("dependencies").and_then(|d| d.as_array()).into_iter().flatten();
        let deps = deps.filter_map(|d| d.as_str()?.split(' ').next().map(str::to_owned));
        graph.entry(name).or_default().extend(deps);
    }
    let outside = ours.iter().flat_map(|p| packages[p].normal.iter()).filter(|d| !packages.contains_key(*d));
    let mut all = closure(&graph, outside.cloned());
    all.extend(ours);
    all
}

/// ARCHITECTURE.md §8's table: per row, the crates' directories, the
/// names in backticks of "may depend on" and of "its tests also use", and
/// whether the row allows everything above it.
struct Row {
    dirs: Vec<String>,
    may: BTreeSet<String>,
    tests: BTreeSet<String>,
    everything_above: bool,
}

fn quoted(cell: &str) -> BTreeSet<String> {
    cell.split('`').skip(1).step_by(2).map(str::to_owned).collect()
}

fn table() -> Vec<Row> {
    let doc = std::fs::read_to_string(Path::new(ROOT).join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let section = doc.split("\n## 8.").nth(1).expect("§8").split("\n## ").next().expect("§8's text");
    let lines = section.lines().skip_while(|l| !l.starts_with("| crate |"));
    let rows: Vec<Row> = lines
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let cells: Vec<&str> = l.trim_matches('|').split('|').map(str::trim).collect();
            assert_eq!(cells.len(), 4, "§8 row with {} cells: {l}", cells.len());
            Row {
                dirs: quoted(cells[0]).into_iter().collect(),
                may: quoted(cells[2]),
                tests: quoted(cells[3]),
                everything_above: cells[2].contains("everything above"),
            }
        })
        .collect();
    assert!(rows.len() > 10, "§8's table not found");
    rows
}

#[test]
fn the_table_in_architecture_md_is_what_the_manifests_say() {
    let packages = workspace();
    let by_dir: BTreeMap<&str, &str> = packages.iter().map(|(n, p)| (p.dir.as_str(), n.as_str())).collect();
    let mut above = BTreeSet::new();
    let mut rowed = BTreeSet::new();
    for row in table() {
        let names: Vec<&str> = row
            .dirs
            .iter()
            .map(|d| {
                *by_dir.get(d.as_str()).unwrap_or_else(|| panic!("§8 names `{d}`, not a workspace crate"))
            })
            .collect();
        let ours = |named: &BTreeSet<String>| -> BTreeSet<String> {
            named.iter().filter(|n| packages.contains_key(*n)).cloned().collect()
        };
        let (may, tests) = (ours(&row.may), ours(&row.tests));
        let workspace_deps = |deps: &BTreeSet<String>| -> BTreeSet<String> {
            deps.iter().filter(|d| packages.contains_key(*d)).cloned().collect()
        };
        let normal: BTreeSet<String> =
            names.iter().flat_map(|n| workspace_deps(&packages[*n].normal)).collect();
        let dev: BTreeSet<String> =
            names.iter().flat_map(|n| workspace_deps(&packages[*n].dev_only)).collect();
        if row.everything_above {
            let beyond: Vec<&String> = normal.difference(&above).collect();
            assert!(beyond.is_empty(), "{names:?} depend on {beyond:?}, not above them in §8");
        } else {
            assert_eq!(normal, may, "{names:?}: the manifests' workspace dependencies, and §8's");
        }
        assert_eq!(dev, tests, "{names:?}: the tests' own workspace dependencies, and §8's");
        for n in names {
            above.insert(n.to_owned());
            rowed.insert(n.to_owned());
        }
    }
    let missing: Vec<&String> = packages.keys().filter(|n| !rowed.contains(*n)).collect();
    assert!(missing.is_empty(), "workspace crates without a row in §8: {missing:?}");
}

#[test]
fn the_controllers_crates_cannot_reach_the_simulator() {
    let graph = workspace_graph(&workspace());
    assert!(reaches(&graph, "upm-cli", "drivers"), "the check must see the launcher link the simulator");
    let controllers = [
        "upm-solver",
        "upm-motion",
        "upm-hardware",
        "rt-core",
        "ipc-types",
        "upm-rig-config",
        "upm-stats",
        "upm-vision",
        "upm-planner",
        "upm-calibrate",
    ];
    for controller in controllers {
        assert!(graph.contains_key(controller), "{controller} is not a workspace package");
        assert!(
            !reaches(&graph, controller, "drivers"),
            "{controller} can reach the simulator and its truth"
        );
    }
}

#[test]
fn the_core_links_no_client_and_none_of_the_tools_crates() {
    let packages = workspace();
    let cli = links(&packages, "upm-cli");
    for name in NOT_IN_THE_CORE.iter().filter(|n| **n != "upm-cli") {
        assert!(cli.contains(*name), "the check must see upm-cli link {name}");
    }
    let core = links(&packages, "upm-core");
    assert!(core.contains("rt-core") && core.contains("iceoryx2"), "{core:?}");
    let found: Vec<&&str> = NOT_IN_THE_CORE.iter().filter(|n| core.contains(**n)).collect();
    assert!(found.is_empty(), "upm-core links {found:?}");
}

/// What the model crates must not link: the transport and the RT runtime.
const NOT_IN_THE_MODEL: [&str; 7] =
    ["iceoryx2", "thread-priority", "triple_buffer", "rtrb", "hdrhistogram", "rt-core", "upm-hardware"];

#[test]
fn the_model_is_pure() {
    let packages = workspace();
    let ws = toml_at(&Path::new(ROOT).join("Cargo.toml"));
    let shared = ws["workspace"]["dependencies"].as_table().expect("[workspace.dependencies]");
    // ipc-types' transport is a default feature: the workspace's entry must
    // switch defaults off, or every dependent gets iceoryx2 with it.
    assert_eq!(
        shared["ipc-types"].get("default-features").and_then(toml::Value::as_bool),
        Some(false),
        "the workspace's ipc-types entry must say default-features = false"
    );
    for model in ["upm-solver", "upm-motion"] {
        let ours = closure(&workspace_graph(&packages), [model.to_owned()]);
        for p in &ours {
            if p == "ipc-types" {
                continue;
            }
            let manifest = toml_at(&Path::new(ROOT).join(&packages[p].dir).join("Cargo.toml"));
            let deps = manifest["dependencies"].as_table().expect("[dependencies]");
            if let Some(entry) = deps.get("ipc-types") {
                let features =
                    entry.get("features").and_then(toml::Value::as_array).cloned().unwrap_or_default();
                assert!(
                    !features.iter().any(|f| f.as_str() == Some("iceoryx2")),
                    "{p} (linked by {model}) turns on ipc-types' iceoryx2"
                );
            }
            let found: Vec<&&str> =
                NOT_IN_THE_MODEL.iter().filter(|n| packages[p].normal.contains(**n)).collect();
            assert!(found.is_empty(), "{p} (linked by {model}) depends on {found:?}");
        }
    }
}
