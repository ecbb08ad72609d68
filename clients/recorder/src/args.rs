//! `upm-recorder` command-line arguments and entry point.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::Context as _;
use clap::Parser;
use rig_config::{ConfigError, ProcessArgs};

use crate::{LogOptions, PlateView, Recorder, RecorderOptions};

#[derive(Debug, Parser)]
#[command(
    name = "upm-recorder",
    version,
    about = "UPM flight recorder (MCAP) and live view (Foxglove WebSocket)"
)]
pub struct RecorderArgs {
    /// `--config` is read for [service] and [plate] and attached to the
    /// recording whole (replay needs it).
    #[command(flatten)]
    pub process: ProcessArgs,
    /// Write the recording here (an existing file is never overwritten).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Serve the Foxglove WebSocket protocol on this localhost port (0: a
    /// free one, printed at start).
    #[arg(long)]
    pub serve: Option<u16>,
    /// Record camera frames' pixels too (headers are always recorded).
    #[arg(long)]
    pub frame_pixels: bool,
    /// Keep at most this many simulator ground-truth messages a second
    /// (0: every one).
    #[arg(long, default_value_t = 100.0)]
    pub truth_hz: f64,
    /// Continue in a new file (`NAME.001.mcap`, …) after this many minutes
    /// (0: one file); each is a recording of its own, with the rig's TOML.
    /// Long runs need it: a file's chunk index stays in memory until it ends.
    #[arg(long, default_value_t = 0.0)]
    pub segment_minutes: f64,
    /// key=value pairs for the recording's metadata (scenario, seed, …).
    #[arg(long = "info", value_parser = parse_info)]
    pub info: Vec<(String, String)>,
}

fn parse_info(s: &str) -> Result<(String, String), String> {
    s.split_once('=')
        .map(|(k, v)| (k.to_owned(), v.to_owned()))
        .ok_or_else(|| format!("--info {s:?}: expected key=value"))
}

/// Record until SIGINT/SIGTERM or `--duration`; prints what was received and lost.
pub fn run_recorder_process(args: RecorderArgs) -> anyhow::Result<()> {
    if args.out.is_none() && args.serve.is_none() {
        anyhow::bail!("nothing to do: give --out FILE, --serve PORT or both");
    }
    let file = args.process.file()?;
    let prefix = args.process.prefix(&file)?;
    let plate = file.section::<PlateView>("plate")?;
    let config_text = match &args.process.config {
        Some(p) => Some(std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?),
        None => None,
    };
    let duration =
        args.process.duration().map_err(|m| anyhow::anyhow!(ConfigError::invalid("--duration", m)))?;
    if !((0.0..1e9).contains(&args.segment_minutes)) {
        anyhow::bail!(ConfigError::invalid(
            "--segment-minutes",
            format!(
                "must be 0 (one file) or a positive number of minutes below 1e9, got {}",
                args.segment_minutes
            )
        ));
    }
    let segment = (args.segment_minutes > 0.0).then(|| Duration::from_secs_f64(args.segment_minutes * 60.0));
    let opts = RecorderOptions {
        prefix,
        log: LogOptions {
            plate,
            mcap: args.out.clone(),
            serve_port: args.serve,
            config_text,
            info: args.info.into_iter().collect::<BTreeMap<_, _>>(),
            segment,
        },
        frame_pixels: args.frame_pixels,
        truth_hz: args.truth_hz,
    };
    let mut recorder = Recorder::start(&opts)?;
    if let Some(port) = recorder.port() {
        println!("upm-recorder: Foxglove WebSocket on ws://127.0.0.1:{port}");
    }
    if let Some(out) = &args.out {
        println!("upm-recorder: recording to {}", out.display());
    }
    let started = Instant::now();
    recorder.run(|| duration.is_some_and(|d| started.elapsed() >= d))?;
    let counts = recorder.finish()?;
    let received: u64 = counts.values().map(|(r, _)| r).sum();
    let lost: u64 = counts.values().filter_map(|(_, l)| *l).sum();
    eprintln!("upm-recorder: {received} messages recorded, {lost} lost");
    for (topic, (r, l)) in &counts {
        if let Some(l) = l.filter(|l| *l > 0) {
            eprintln!("upm-recorder: {topic}: {l} lost of {}", r + l);
        }
    }
    Ok(())
}
