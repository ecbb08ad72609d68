//! `upm-line` as a stranger starts it: each wrong start is refused in one
//! line naming what is wrong, with exit status 1, before any server
//! binds. (This test also makes `cargo test` build the binary, which
//! `upm run --opcua/--modbus` starts.)

use std::process::Command;

fn refused(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_upm-line")).args(args).output().expect("running upm-line");
    assert_eq!(out.status.code(), Some(1), "{args:?}: {out:?}");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let last = err.lines().last().unwrap_or_default().to_owned();
    assert!(last.starts_with("upm-line: error: "), "{args:?}: {err}");
    last
}

#[test]
fn wrong_starts_are_refused_in_one_line() {
    let prefix = format!("upm_line_process_{}_", std::process::id());
    let missing = std::env::temp_dir().join(format!("upm_line_no_users_{}.toml", std::process::id()));
    let missing = missing.display().to_string();

    let e = refused(&["--prefix", &prefix, "--users", &missing, "--opcua", "127.0.0.1:0"]);
    assert!(e.contains(&missing), "{e}");

    let e = refused(&["--prefix", &prefix]);
    assert!(e.contains("nothing to serve"), "{e}");

    let e = refused(&["--prefix", &prefix, "--opcua", "127.0.0.1:0", "--duration=0"]);
    assert!(e.contains("--duration"), "{e}");

    ipc_types::rig_node::remove_prefix_segment(&prefix);
}
