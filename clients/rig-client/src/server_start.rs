//! What a client with servers reads before it serves (the rig, how long,
//! its users), and when it stops: SIGINT, SIGTERM or `--duration`.

use std::path::Path;
use std::time::Duration;

use rig_config::{ConfigError, ProcessArgs};
use upm_users::Users;

use crate::rig_prefix::rig_prefix;

#[derive(Debug)]
pub struct ServerStart {
    pub prefix: String,
    pub duration: Option<Duration>,
    /// The users file's users; none without one.
    pub users: Users,
}

impl ServerStart {
    /// `name` is the process (`upm-line`); `without_users` says what a
    /// missing users file means for it.
    pub fn read(
        process: &ProcessArgs,
        users: Option<&Path>,
        name: &str,
        without_users: &str,
    ) -> anyhow::Result<Self> {
        let prefix = rig_prefix(process)?;
        let duration =
            process.duration().map_err(|m| anyhow::anyhow!(ConfigError::invalid("--duration", m)))?;
        let users = match users {
            Some(path) => Users::load(path)?,
            None => {
                eprintln!("{name}: no --users file: {without_users}");
                Users::default()
            }
        };
        Ok(Self { prefix, duration, users })
    }
}

/// Resolves on SIGINT, SIGTERM or once `duration` has passed.
pub async fn until_stopped(duration: Option<Duration>) -> std::io::Result<()> {
    let mut term = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())?;
    let elapsed = async {
        match duration {
            Some(d) => tokio::time::sleep(d).await,
            None => std::future::pending().await,
        }
    };
    tokio::select! {
        r = tokio::signal::ctrl_c() => r,
        _ = term.recv() => Ok(()),
        () = elapsed => Ok(()),
    }
}
