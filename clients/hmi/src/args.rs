//! `upm-hmi` arguments and entry point: the rig's view, then the page's
//! server on a small tokio runtime, until SIGINT/SIGTERM or `--duration`.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

use axum::extract::ws::Utf8Bytes;
use clap::Parser;
use rig_config::ProcessArgs;
use tokio::sync::watch;
use upm_rig_client::rig_view::{RigView, ViewOptions};
use upm_rig_client::server_start::{ServerStart, until_stopped};

use crate::counters::HmiCounters;
use crate::routes::{AppState, router};

#[derive(Debug, Parser)]
#[command(
    name = "upm-hmi",
    version,
    about = "UPM's operator page: the live plate, its counters and its controls in a browser"
)]
pub struct HmiArgs {
    /// The rig: `--prefix`, else the config's, else the one rig running.
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Serve the page here (bind a LAN address only on a trusted network:
    /// the page is plain HTTP).
    #[arg(long, default_value = "127.0.0.1:8080")]
    pub addr: SocketAddr,
    /// The users file of the line interface (`upm users add`); without it
    /// no one may log in, and the page only shows.
    #[arg(long)]
    pub users: Option<PathBuf>,
    /// Where "load recipe" NAME looks for `NAME.toml` (a path is taken as
    /// it is).
    #[arg(long, default_value = "recipes")]
    pub recipes: PathBuf,
}

/// Serve until SIGINT/SIGTERM or `--duration`.
pub fn run_hmi_process(args: HmiArgs) -> anyhow::Result<()> {
    let ServerStart { prefix, duration, users } = ServerStart::read(
        &args.process,
        args.users.as_deref(),
        "upm-hmi",
        "every login is refused, the page only shows",
    )?;
    let counters = Arc::new(HmiCounters::default());
    // Started by hand, it still keeps off the motor's CPU once the core's
    // telemetry names the core.
    let options = ViewOptions { node_name: "upm-hmi", part_states: true, keep_off_motor_cpu: true };
    let view = Arc::new(RigView::start(&prefix, options, counters.clone())?);
    // Two workers: the page never needs more, and never runs an RT thread.
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
    runtime.block_on(async {
        let listener = tokio::net::TcpListener::bind(args.addr)
            .await
            .map_err(|e| anyhow::anyhow!("--addr {}: cannot listen: {e}", args.addr))?;
        let (stop_tx, stop) = watch::channel(false);
        let live = Arc::new(watch::Sender::new(Utf8Bytes::from_static("{}")));
        let state = Arc::new(AppState {
            prefix: prefix.clone(),
            view: view.clone(),
            users: Arc::new(users),
            sessions: Default::default(),
            throttle: Default::default(),
            counters: counters.clone(),
            live: live.clone(),
            recipes_dir: args.recipes.clone(),
            stop: stop.clone(),
        });
        let publisher = tokio::spawn(crate::live_message::publish(view.clone(), live, stop.clone()));
        println!("upm-hmi: rig {prefix:?}; the page on http://{}/", listener.local_addr()?);
        let until = async move {
            if let Err(e) = until_stopped(duration).await {
                eprintln!("upm-hmi: waiting for a signal: {e}; stopping");
            }
            let _ = stop_tx.send(true);
        };
        let app = router(state).into_make_service_with_connect_info::<SocketAddr>();
        axum::serve(listener, app).with_graceful_shutdown(until).await?;
        let _ = publisher.await;
        anyhow::Ok(())
    })?;
    let counts: Vec<String> = counters.all().iter().map(|(k, v)| format!("{k} {v}")).collect();
    println!("upm-hmi: stopped; {}", counts.join(", "));
    Ok(())
}
