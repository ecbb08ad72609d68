//! `upm-line` arguments and entry point: the rig's view, then the OPC UA
//! and Modbus servers on a small tokio runtime, until SIGINT/SIGTERM or
//! `--duration`.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

use clap::Parser;
use rig_config::ProcessArgs;
use tokio_util::sync::CancellationToken;
use upm_rig_client::server_start::{ServerStart, until_stopped};

use crate::counters::LineCounters;
use crate::opcua_server::{OpcUaOptions, serve as serve_opcua};
use upm_rig_client::rig_view::{RigView, ViewOptions};

#[derive(Debug, Parser)]
#[command(
    name = "upm-line",
    version,
    about = "UPM's line interface: OPC UA and Modbus TCP for robots and PLCs"
)]
pub struct LineArgs {
    /// The rig: `--prefix`, else the config's, else the one rig running.
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Serve OPC UA here (`opc.tcp://ADDR/`, e.g. 127.0.0.1:4840).
    #[arg(long)]
    pub opcua: Option<SocketAddr>,
    /// Serve Modbus TCP here (e.g. 127.0.0.1:5020; bind a LAN address
    /// only on a trusted cell network: Modbus has no users).
    #[arg(long)]
    pub modbus: Option<SocketAddr>,
    /// The users file (`upm users add`); without it no one may call methods.
    #[arg(long)]
    pub users: Option<PathBuf>,
    /// The OPC UA server's certificates: its own (made on first start) and
    /// the client certificates it trusts (`trusted/`).
    #[arg(long, default_value = "out/line/pki")]
    pub pki: PathBuf,
    /// Who picks: `external` (a robot through `Rig.Picked` or holding
    /// register 10; a real rig's) or `builtin` (the simulator's own robot:
    /// picks from outside are refused).
    #[arg(long, default_value = "external", value_parser = ["external", "builtin"])]
    pub robot: String,
    /// Where `LoadRecipe(NAME)` looks for `NAME.toml` (a path is taken as
    /// it is).
    #[arg(long, default_value = "recipes")]
    pub recipes: PathBuf,
}

/// Serve until SIGINT/SIGTERM or `--duration`.
pub fn run_line_process(args: LineArgs) -> anyhow::Result<()> {
    let ServerStart { prefix, duration, users } = ServerStart::read(
        &args.process,
        args.users.as_deref(),
        "upm-line",
        "every OPC UA method call is refused",
    )?;
    if args.opcua.is_none() && args.modbus.is_none() {
        anyhow::bail!("nothing to serve: give --opcua ADDR, --modbus ADDR or both");
    }
    let counters = Arc::new(LineCounters::default());
    let options = ViewOptions { node_name: "upm-line", part_states: false, keep_off_motor_cpu: false };
    let view = Arc::new(RigView::start(&prefix, options, counters.clone())?);
    let builtin_robot = args.robot == "builtin";
    // Two workers: the line never needs more, and never runs on an RT thread.
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
    runtime.block_on(async {
        let stop = CancellationToken::new();
        let opcua = match args.opcua {
            Some(addr) => {
                let opts = OpcUaOptions {
                    addr,
                    pki_dir: args.pki.clone(),
                    users,
                    builtin_robot,
                    recipes_dir: args.recipes.clone(),
                };
                Some(serve_opcua(opts, view.clone(), counters.clone()).await?)
            }
            None => None,
        };
        let mut modbus = args.modbus.map(|addr| {
            let stopped = stop.clone();
            tokio::spawn(crate::modbus_server::serve(
                addr,
                builtin_robot,
                view.clone(),
                counters.clone(),
                async move {
                    stopped.cancelled().await;
                },
            ))
        });
        let shown = |a: Option<SocketAddr>| a.map_or_else(|| "off".to_owned(), |a| a.to_string());
        println!(
            "upm-line: rig {prefix:?}; OPC UA on {}, Modbus TCP on {}",
            args.opcua.map_or_else(|| "off".to_owned(), |a| format!("opc.tcp://{a}/")),
            shown(args.modbus)
        );
        let modbus_ended = async {
            match modbus.as_mut() {
                Some(task) => task.await,
                None => std::future::pending().await,
            }
        };
        let failed = tokio::select! {
            r = until_stopped(duration) => r.err().map(anyhow::Error::from),
            r = modbus_ended => {
                modbus = None;
                Some(match r {
                    Ok(Err(e)) => e,
                    Ok(Ok(())) => anyhow::anyhow!("the Modbus server stopped"),
                    Err(e) => anyhow::anyhow!("the Modbus server failed: {e}"),
                })
            }
        };
        stop.cancel();
        if let Some((handle, task)) = opcua {
            handle.cancel();
            let _ = task.await;
        }
        if let Some(task) = modbus {
            let _ = task.await;
        }
        failed.map_or(Ok(()), Err)
    })?;
    let counts: Vec<String> = counters.all().iter().map(|(k, v)| format!("{k} {v}")).collect();
    println!("upm-line: stopped; refused: {}", counts.join(", "));
    Ok(())
}
