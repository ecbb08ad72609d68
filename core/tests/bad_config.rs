//! `upm-core --config F` refuses a bad file in one line naming the file and
//! the field, before it touches anything, and exits 1. (This test also
//! makes `cargo test` build the binary the launcher's tests start.)

use std::process::Command;

/// upm-core's stderr and exit code on `text` as its config.
fn refused(tag: &str, text: &str) -> (String, Option<i32>) {
    let path = std::env::temp_dir().join(format!("upm_core_bad_{tag}_{}.toml", std::process::id()));
    std::fs::write(&path, text).expect("config file");
    let out = Command::new(env!("CARGO_BIN_EXE_upm-core"))
        .arg("--config")
        .arg(&path)
        .args(["--prefix", &format!("upmt_bad_{tag}_")])
        .output()
        .expect("upm-core");
    let _ = std::fs::remove_file(&path);
    (String::from_utf8_lossy(&out.stderr).into_owned(), out.status.code())
}

#[test]
fn a_bad_config_is_one_line_naming_the_field() {
    for (tag, text, field) in [
        ("type", "[motion]\ntick_hz = \"fast\"\n", "motion.tick_hz: "),
        ("range", "[safety]\nparts_max_age_ms = -1.0\n", "safety.parts_max_age_ms: "),
        ("zero", "[safety]\nparts_max_age_ms = 0\n", "safety.parts_max_age_ms must be"),
        ("unknown", "[visio]\nframe_hz = 30.0\n", "visio: "),
        ("field", "[sim]\nseeds = 3\n", "sim.seeds: "),
    ] {
        let (stderr, code) = refused(tag, text);
        assert_eq!(code, Some(1), "{tag}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{tag}: {stderr}");
        assert!(stderr.starts_with("upm-core: error: "), "{tag}: {stderr}");
        assert!(stderr.contains(field), "{tag}: wanted {field:?} in {stderr}");
    }
}
