use std::path::PathBuf;
use std::time::Duration;

use crate::{ConfigError, RigFile, ServiceSection};

/// The arguments every UPM process takes: which rig file, which rig, and
/// how long to run. Flattened into each process's own arguments.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ProcessArgs {
    /// Rig config (TOML). Without it the built-in defaults are used.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Override service.prefix of the config.
    #[arg(long)]
    pub prefix: Option<String>,
    /// Stop by itself after this many seconds (default: run until Ctrl-C).
    #[arg(long)]
    pub duration: Option<f64>,
}

impl ProcessArgs {
    /// The rig file `--config` names (the built-in defaults without one).
    pub fn file(&self) -> Result<RigFile, ConfigError> {
        RigFile::load_or_default(self.config.as_deref())
    }

    /// The rig's prefix: `--prefix`, else `[service]` of `file`.
    pub fn prefix(&self, file: &RigFile) -> Result<String, ConfigError> {
        let service = file.section::<ServiceSection>("service")?;
        service.prefix_or(self.prefix.as_deref()).map_err(|m| ConfigError::invalid(file.shown(), m))
    }

    /// `--duration`, checked.
    pub fn duration(&self) -> Result<Option<Duration>, String> {
        match self.duration {
            Some(s) if s.is_finite() && s > 0.0 && s < 1e12 => Ok(Some(Duration::from_secs_f64(s))),
            Some(s) => Err(format!("--duration must be a positive number of seconds, got {s}")),
            None => Ok(None),
        }
    }
}
