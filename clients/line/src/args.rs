//! `upm-line` arguments and entry point: the rig's view, then the OPC UA
//! and Modbus servers on a small tokio runtime, until SIGINT/SIGTERM or
//! `--duration`.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

use clap::Parser;
use rig_config::{ConfigError, ProcessArgs};
use upm_users::Users;

use crate::counters::LineCounters;
use crate::opcua_server::{OpcUaOptions, serve as serve_opcua};
use crate::rig_view::RigView;

#[derive(Debug, Parser)]
#[command(name = "upm-line", version, about = "UPM's line interface: OPC UA and Modbus TCP for robots and PLCs")]
pub struct LineArgs {
    /// The rig: `--prefix`, else the config's, else the one rig running.
    #[command(flatten)]
    pub process: ProcessArgs,
    /// OPC UA endpoint address (`opc.tcp://ADDR/`).
    #[arg(long, default_value = "127.0.0.1:4840")]
    pub opcua: SocketAddr,
    /// Modbus TCP address (localhost unless given).
    #[arg(long, default_value = "127.0.0.1:5020")]
    pub modbus: SocketAddr,
    /// The users file (`upm users add`); without it no one may call methods.
    #[arg(long)]
    pub users: Option<PathBuf>,
    /// The OPC UA server's certificates: its own (made on first start) and
    /// the client certificates it trusts (`trusted/`).
    #[arg(long, default_value = "out/line/pki")]
    pub pki: PathBuf,
    /// What `Rig.Recipe` shows.
    #[arg(long, default_value = "")]
    pub recipe: String,
}

/// The rig's prefix: given, or the only rig running (as `upm status`).
fn prefix(process: &ProcessArgs) -> anyhow::Result<String> {
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

/// Serve until SIGINT/SIGTERM or `--duration`.
pub fn run_line_process(args: LineArgs) -> anyhow::Result<()> {
    let prefix = prefix(&args.process)?;
    let duration =
        args.process.duration().map_err(|m| anyhow::anyhow!(ConfigError::invalid("--duration", m)))?;
    let users = match &args.users {
        Some(path) => Users::load(path)?,
        None => {
            eprintln!("upm-line: no --users file: every OPC UA method call is refused");
            Users::default()
        }
    };
    let view = Arc::new(RigView::start(&prefix, &args.recipe)?);
    let counters = Arc::new(LineCounters::default());
    // Two workers: the line never needs more, and never runs on an RT thread.
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
    runtime.block_on(async {
        let opts = OpcUaOptions { addr: args.opcua, pki_dir: args.pki.clone(), users };
        let (handle, opcua) = serve_opcua(opts, view.clone(), counters.clone()).await?;
        let token = handle.token().clone();
        let modbus_stop = token.clone();
        let modbus = tokio::spawn(crate::modbus_server::serve(
            args.modbus,
            view.clone(),
            counters.clone(),
            async move { modbus_stop.cancelled().await },
        ));
        println!("upm-line: rig {prefix:?}; OPC UA on opc.tcp://{}/, Modbus TCP on {}", args.opcua, args.modbus);
        let mut term = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())?;
        let until = async {
            match duration {
                Some(d) => tokio::time::sleep(d).await,
                None => std::future::pending().await,
            }
        };
        tokio::select! {
            _ = tokio::signal::ctrl_c() => {}
            _ = term.recv() => {}
            () = until => {}
            r = modbus => { handle.cancel(); r??; anyhow::bail!("the Modbus server stopped"); }
        }
        handle.cancel();
        let _ = opcua.await;
        anyhow::Ok(())
    })?;
    let counts: Vec<String> = counters.all().iter().map(|(k, v)| format!("{k} {v}")).collect();
    println!("upm-line: stopped; refused: {}", counts.join(", "));
    Ok(())
}
