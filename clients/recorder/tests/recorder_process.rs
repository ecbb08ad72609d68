//! `upm-recorder` as a stranger starts it: each wrong start is refused in
//! one line naming what is wrong, with exit status 1. (This test also
//! makes `cargo test` build the binary, which `upm run` starts when it is
//! there, rather than an older one.)

use std::process::Command;

fn refused(args: &[&str]) -> String {
    let out =
        Command::new(env!("CARGO_BIN_EXE_upm-recorder")).args(args).output().expect("running upm-recorder");
    assert_eq!(out.status.code(), Some(1), "{args:?}: {out:?}");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    err
}

#[test]
fn wrong_starts_are_refused_in_one_line() {
    let prefix = format!("upm_recorder_process_{}_", std::process::id());
    let out = std::env::temp_dir().join(format!("upm_recorder_process_{}.mcap", std::process::id()));
    let out = out.display().to_string();

    let e = refused(&["--prefix", &prefix]);
    assert!(e.contains("nothing to do"), "{e}");

    for bad in ["-1", "NaN", "inf", "1e12"] {
        let e = refused(&["--prefix", &prefix, "--out", &out, &format!("--segment-minutes={bad}")]);
        assert!(e.contains("--segment-minutes"), "{bad}: {e}");
    }
    assert!(!std::path::Path::new(&out).exists(), "a refused start wrote {out}");
}
