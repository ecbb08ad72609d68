//! A live USB/UVC camera as a frame source, through the kernel's V4L2 API
//! with memory-mapped streaming (`v4l`, its `v4l2` backend: ioctls on the
//! device node, no system library). The camera is asked for 8-bit grey
//! (`GREY`) at the calibrated size; a webcam that only offers `YUYV` gives
//! its luma bytes. Each dequeued buffer is copied once, into the shared
//! memory frame that vision reads (V4L2 cannot capture into iceoryx2's
//! segment). The frame's stamp is the driver's monotonic capture time when
//! the driver gives one (UVC: start of exposure), else the dequeue time.

use std::path::Path;
use std::time::Duration;

use iceoryx2::prelude::*;
use ipc_types::rig_node::rig_node;
use ipc_types::{FrameHeader, monotonic_now_ns};
use v4l::buffer::{Flags, Type};
use v4l::io::traits::CaptureStream;
use v4l::video::Capture;
use v4l::{Device, FourCC};

use crate::live_stats::LiveStats;

/// Buffers the driver fills ahead of us.
const BUFFERS: u32 = 4;

/// How the device's pixels become mono8.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Pixels {
    Grey,
    /// Y0 U Y1 V: every other byte is luma.
    Yuyv,
}

/// Capture from the V4L2 device at `path` at `width × height` (the
/// calibration's size) and `fps`, publishing on `prefix` until SIGINT,
/// SIGTERM or `duration`.
pub fn run_v4l2(
    prefix: &str,
    path: &Path,
    (width, height): (u32, u32),
    fps: f64,
    duration: Option<Duration>,
) -> anyhow::Result<LiveStats> {
    let shown = path.display();
    let dev = Device::with_path(path).map_err(|e| anyhow::anyhow!("{shown}: no V4L2 camera there ({e})"))?;
    let caps = dev.query_caps().map_err(|e| anyhow::anyhow!("{shown}: not a V4L2 device ({e})"))?;
    if !caps.capabilities.contains(v4l::capability::Flags::VIDEO_CAPTURE) {
        anyhow::bail!("{shown} ({}): not a video capture device", caps.card);
    }
    let pixels =
        negotiate(&dev, width, height).map_err(|e| anyhow::anyhow!("{shown} ({}): {e}", caps.card))?;
    if fps.is_finite() && fps >= 1.0 {
        // A camera that cannot do the rate keeps its own; the stamps tell.
        let _ = dev.set_params(&v4l::video::capture::Parameters::with_fps(fps.round() as u32));
    }
    let format = dev.format().map_err(|e| anyhow::anyhow!("{shown}: reading the format back: {e}"))?;
    let stride = format.stride as usize;
    let mut stream = v4l::io::mmap::Stream::with_buffers(&dev, Type::VideoCapture, BUFFERS)
        .map_err(|e| anyhow::anyhow!("{shown}: mapping capture buffers: {e}"))?;
    stream.set_timeout(Duration::from_millis(200));
    let node = rig_node(prefix, None, SignalHandlingMode::HandleTerminationRequests)?;
    let mut out = crate::run::FrameOut::open(&node, (width * height) as usize)?;
    let mut grey = vec![0u8; (width * height) as usize];
    let end = duration.map(|d| monotonic_now_ns() + d.as_nanos() as u64);
    let mut stats = LiveStats::default();
    let mut last_sequence: Option<u32> = None;
    let row_bytes = match pixels {
        Pixels::Grey => width as usize,
        Pixels::Yuyv => 2 * width as usize,
    };
    loop {
        if end.is_some_and(|e| monotonic_now_ns() >= e) || node.wait(Duration::ZERO).is_err() {
            return Ok(stats);
        }
        let (buf, meta) = match stream.next() {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => continue,
            Err(e) => anyhow::bail!("{shown}: capture stopped: {e}"),
        };
        let received = monotonic_now_ns();
        if let Some(last) = last_sequence {
            stats.dropped += u64::from(meta.sequence.wrapping_sub(last).saturating_sub(1));
        }
        last_sequence = Some(meta.sequence);
        let used = (meta.bytesused as usize).min(buf.len());
        if meta.flags.contains(Flags::ERROR) || used < stride * (height as usize - 1) + row_bytes {
            stats.bad_buffers += 1;
            continue;
        }
        let packed = pixels == Pixels::Grey && stride == width as usize;
        if !packed {
            for (v, dst) in grey.chunks_exact_mut(width as usize).enumerate() {
                let row = &buf[v * stride..v * stride + row_bytes];
                match pixels {
                    Pixels::Grey => dst.copy_from_slice(row),
                    Pixels::Yuyv => dst.iter_mut().zip(row.iter().step_by(2)).for_each(|(d, y)| *d = *y),
                }
            }
        }
        let stamp_ns = if meta.flags.contains(Flags::TIMESTAMP_MONOTONIC) {
            (meta.timestamp.sec as u64) * 1_000_000_000 + (meta.timestamp.usec as u64) * 1_000
        } else {
            received
        };
        stats.published += 1;
        let header = FrameHeader { seq: stats.published, stamp_ns, ..FrameHeader::mono8(width, height) };
        // Packed grey goes straight from the driver's buffer to shared
        // memory; anything else through one row-by-row conversion.
        out.publish(header, if packed { &buf[..(width * height) as usize] } else { &grey })?;
    }
}

/// Ask for GREY, else YUYV, at exactly `width × height`.
fn negotiate(dev: &Device, width: u32, height: u32) -> Result<Pixels, String> {
    let mut offered = Vec::new();
    for (fourcc, pixels) in [(b"GREY", Pixels::Grey), (b"YUYV", Pixels::Yuyv)] {
        let mut want = dev.format().map_err(|e| format!("reading the format: {e}"))?;
        want.width = width;
        want.height = height;
        want.fourcc = FourCC::new(fourcc);
        let got = dev.set_format(&want).map_err(|e| format!("setting the format: {e}"))?;
        if got.fourcc == want.fourcc && got.width == width && got.height == height {
            return Ok(pixels);
        }
        offered.push(format!("{} {}×{}", got.fourcc, got.width, got.height));
    }
    Err(format!(
        "cannot capture GREY or YUYV at {width}×{height} (the calibration's size); it offered {}",
        offered.join(", ")
    ))
}
