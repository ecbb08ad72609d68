//! No library crate of the workspace holds more than 5,000 lines of Rust
//! under `src/` (ARCHITECTURE.md §8): past that a crate mixes concerns
//! and should split along its seams.

use std::path::Path;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
const MOST_LINES: usize = 5_000;

fn rust_lines(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else { return 0 };
    entries
        .flatten()
        .map(|e| e.path())
        .map(|p| match p.extension() {
            _ if p.is_dir() => rust_lines(&p),
            Some(x) if x == "rs" => std::fs::read_to_string(&p).map_or(0, |t| t.lines().count()),
            _ => 0,
        })
        .sum()
}

#[test]
fn no_crate_holds_more_than_5000_lines() {
    let ws: toml::Table = std::fs::read_to_string(Path::new(ROOT).join("Cargo.toml"))
        .expect("Cargo.toml")
        .parse()
        .expect("the workspace manifest");
    let members = ws["workspace"]["members"].as_array().expect("members");
    let mut counted = Vec::new();
    for m in members {
        let dir = m.as_str().expect("a member path");
        counted.push((dir, rust_lines(&Path::new(ROOT).join(dir).join("src"))));
    }
    // The count must see the code: the largest crates hold thousands.
    assert!(counted.iter().map(|c| c.1).sum::<usize>() > 20_000, "{counted:?}");
    let over: Vec<_> = counted.iter().filter(|c| c.1 > MOST_LINES).collect();
    assert!(over.is_empty(), "crates over {MOST_LINES} lines of Rust: {over:?}");
}
