//! Which rig a client serves: `--prefix`, else the config's, else the one
//! rig running (as `upm status` finds it).

use rig_config::ProcessArgs;

/// The rig's prefix; none or several running without `--prefix` is an
/// error naming them.
pub fn rig_prefix(process: &ProcessArgs) -> anyhow::Result<String> {
    if process.prefix.is_some() || process.config.is_some() {
        let file = process.file()?;
        return Ok(process.prefix(&file)?);
    }
    let rigs = ipc_types::discovery::running_rigs().map_err(|e| anyhow::anyhow!("looking for rigs: {e}"))?;
    match rigs.as_slice() {
        [one] => Ok(one.name.clone()),
        [] => anyhow::bail!("no rig is running: start one, or give --prefix"),
        many => anyhow::bail!(
            "{} rigs are running ({}): give --prefix",
            many.len(),
            many.iter().map(|r| r.name.as_str()).collect::<Vec<_>>().join(", ")
        ),
    }
}
