//! Which program runs each process of a rig. The RT core is its own small
//! binary, `upm-core`; each client runs its own binary (`upm-vision`,
//! `upm-planner`, `upm-camera`, `upm-recorder`) when it is built next to
//! `upm`, else `upm`'s hidden subcommand for it (`upm vision`, …), the
//! same code linked into `upm`.

use std::path::PathBuf;

use anyhow::Context;

/// The `upm` executable (`UPM_EXE` to use another build); the processes'
/// binaries are looked for next to it.
pub(crate) fn upm_exe() -> anyhow::Result<PathBuf> {
    if let Some(p) = std::env::var_os("UPM_EXE") {
        return Ok(PathBuf::from(p));
    }
    std::env::current_exe().context("locating the upm binary")
}

/// The RT core: `UPM_CORE_EXE`, else `upm-core` next to `upm`. Never `upm`
/// itself: the core must not lock and carry the whole CLI.
pub(crate) fn core_exe() -> anyhow::Result<PathBuf> {
    if let Some(p) = std::env::var_os("UPM_CORE_EXE") {
        return Ok(PathBuf::from(p));
    }
    let exe = upm_exe()?.with_file_name("upm-core");
    if !exe.is_file() {
        anyhow::bail!(
            "{} is missing: build every process with `cargo build --release` (or set UPM_CORE_EXE)",
            exe.display()
        );
    }
    Ok(exe)
}

/// A client's program and the arguments before its own: `name` (e.g.
/// `upm-vision`) next to `upm`, else `upm vision`.
pub fn client(name: &str) -> anyhow::Result<(PathBuf, Vec<String>)> {
    let upm = upm_exe()?;
    let own = upm.with_file_name(name);
    if own.is_file() {
        return Ok((own, Vec::new()));
    }
    Ok((upm, vec![name.trim_start_matches("upm-").to_owned()]))
}

/// A process that has no `upm` subcommand (its crate is not linked into
/// `upm`): `name` next to `upm`.
pub fn own_binary(name: &str) -> anyhow::Result<PathBuf> {
    let exe = upm_exe()?.with_file_name(name);
    if !exe.is_file() {
        anyhow::bail!("{} is missing: build every process with `cargo build --release`", exe.display());
    }
    Ok(exe)
}
