//! Frame stamp → PartStates across processes, for `upm bench vision`: the
//! bench publishes already rendered frames on `upm/camera/frame` at the
//! camera's rate, each stamped with the clock as it is sent (a camera that
//! stamps at readout), and wakes vision through the frame event; a real
//! `upm vision` process (its own calibration file, single-threaded,
//! unpinned) segments, tracks and publishes PartStates stamped with the
//! frame's stamp, then notifies the core's inbox. The bench stands in for
//! the core: it sleeps on the inbox event and takes `now − stamp` when the
//! message arrives, and it holds the PM QoS request a running core holds
//! (/dev/cpu_dma_latency = 0, when it may). So the figure holds the
//! frame's transport, vision's wake-up and work, and the PartStates hop to
//! the core.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::Context;
use iceoryx2::prelude::*;
use ipc_types::rig_node::{remove_prefix_segment, rig_node, unique_prefix};
use ipc_types::wake_event::{WakeEvent, wake_listener};
use ipc_types::{FrameHeader, PartStates, monotonic_now_ns, service_names};
use serde::Serialize;
use upm_camera::FrameOut;
use upm_vision::VisionSection;
use upm_vision::calibration::Calibration;

/// Frames sent before timing starts (vision's start-up, first tracks).
const WARM_UP: usize = 10;

/// p50, p99, max (µs) of frame stamp → PartStates at the core's side, and
/// how many frames came back.
#[derive(Debug, Clone, Copy)]
pub struct Latency {
    pub p50_us: f64,
    pub p99_us: f64,
    pub max_us: f64,
    pub answered: usize,
    pub sent: usize,
    /// Of which the source's own part: stamp → frame in shared memory and
    /// vision notified (the copy into the loaned sample), p50 µs.
    pub publish_p50_us: f64,
    /// Whether the PM QoS request was held, as a running core holds it.
    pub pm_qos: bool,
}

#[derive(Serialize)]
struct RigFile<'a> {
    vision: &'a VisionSection,
}

/// Send `frames` (each `width × height` mono8) `rounds` times over at
/// `frame_hz` to a `upm vision` process configured by `vision` (its
/// calibration written into `dir`).
pub fn measure(
    cal: &Calibration,
    vision: &VisionSection,
    frames: &[&[u8]],
    rounds: usize,
    frame_hz: f64,
    dir: &Path,
) -> anyhow::Result<Latency> {
    let (w, h) = (cal.camera.width, cal.camera.height);
    let cal_path = dir.join(format!("latency_calibration_{w}x{h}.toml"));
    cal.save(&cal_path).map_err(anyhow::Error::msg)?;
    let section = VisionSection {
        source: rig_config::frame_rate::FRAMES_SOURCE.into(),
        calibration: cal_path.display().to_string(),
        frame_hz,
        ..vision.clone()
    };
    let rig = dir.join(format!("latency_rig_{w}x{h}.toml"));
    std::fs::write(&rig, toml::to_string(&RigFile { vision: &section })?)?;
    let prefix = unique_prefix("upm_bench_vision");
    let node = rig_node(&prefix, None, SignalHandlingMode::Disabled)?;
    let mut out = FrameOut::open(&node, (w * h) as usize)?;
    let parts = ipc_types::ports::subscriber::<PartStates>(&node, service_names::PART_STATES)?;
    let woken = wake_listener(&node, WakeEvent::Inbox)?;
    let (program, first) = upm_commands::launcher::programs::client("upm-vision")?;
    let mut child = Command::new(program)
        .args(first)
        .arg("--config")
        .arg(&rig)
        .args(["--prefix", &prefix])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .context("starting upm-vision")?;
    let pm_qos = rt_core::rt_setup::hold_cpu_dma_latency(0).ok();
    let result = exchange(&mut out, &parts, &woken, frames, rounds, frame_hz, (w, h))
        .map(|l| Latency { pm_qos: pm_qos.is_some(), ..l });
    drop(pm_qos);
    // SAFETY: SIGINT to the child we started; it stops cleanly on it.
    #[allow(unsafe_code)]
    unsafe {
        libc::kill(child.id() as i32, libc::SIGINT);
    }
    let _ = child.wait();
    drop((out, parts, woken, node));
    remove_prefix_segment(&prefix);
    let _ = std::fs::remove_file(&rig);
    let _ = std::fs::remove_file(&cal_path);
    result
}

fn exchange(
    out: &mut FrameOut,
    parts: &ipc_types::ports::Sub<PartStates>,
    woken: &iceoryx2::port::listener::Listener<ipc::Service>,
    frames: &[&[u8]],
    rounds: usize,
    frame_hz: f64,
    (w, h): (u32, u32),
) -> anyhow::Result<Latency> {
    let period = Duration::from_secs_f64(1.0 / frame_hz);
    // Vision's subscriber must be there before the first frame counts:
    // frames are not kept for late subscribers.
    let started = Instant::now();
    let mut seq = 0u64;
    let mut answered_warm_up = false;
    let mut ages = Vec::new();
    let mut publishing = Vec::new();
    let total = WARM_UP + rounds * frames.len();
    let mut sent = 0;
    while sent < total {
        let pixels = frames[sent % frames.len()];
        seq += 1;
        let stamp = monotonic_now_ns();
        out.publish(FrameHeader { seq, stamp_ns: stamp, ..FrameHeader::mono8(w, h) }, pixels)?;
        let published = monotonic_now_ns() - stamp;
        let deadline = Instant::now() + period;
        let mut answer = None;
        while Instant::now() < deadline {
            woken
                .timed_wait(|_| {}, deadline.saturating_duration_since(Instant::now()))
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            while let Some(s) = parts.receive().map_err(|e| anyhow::anyhow!("{e:?}"))? {
                if s.payload().stamp_ns == stamp {
                    answer = Some(monotonic_now_ns() - stamp);
                }
            }
        }
        if !answered_warm_up {
            // Until vision answers, frames do not count.
            answered_warm_up = answer.is_some();
            anyhow::ensure!(started.elapsed() < Duration::from_secs(30), "upm vision never answered a frame");
            continue;
        }
        sent += 1;
        if sent > WARM_UP
            && let Some(ns) = answer
        {
            ages.push(ns as f64 / 1e3);
            publishing.push(published as f64 / 1e3);
        }
    }
    ages.sort_by(f64::total_cmp);
    publishing.sort_by(f64::total_cmp);
    let at = |q: f64| upm_stats::percentile(&ages, q).unwrap_or(f64::NAN);
    Ok(Latency {
        p50_us: at(0.5),
        p99_us: at(0.99),
        max_us: ages.last().copied().unwrap_or(f64::NAN),
        answered: ages.len(),
        sent: total - WARM_UP,
        publish_p50_us: upm_stats::percentile(&publishing, 0.5).unwrap_or(f64::NAN),
        pm_qos: false,
    })
}
