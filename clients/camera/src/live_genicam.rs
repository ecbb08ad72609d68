//! A live GenICam camera (GigE Vision, USB3 Vision) as a frame source,
//! through Aravis (`aravis`, linking the system's `libaravis-0.8`): Mono8
//! at the calibrated size from the sensor's corner, continuous
//! acquisition into a few buffers that Aravis's stream thread fills and we
//! hand back after each frame. Each frame is copied once, into the shared
//! memory frame vision reads. Aravis's timestamps are the camera's clock
//! or the wall clock, neither ours: the stamp is the monotonic time the
//! buffer reached us.
//!
//! Ids starting with `Fake` enable Aravis's built-in fake camera
//! (`Fake_1`), which is how this path is tested without hardware.

use std::time::Duration;

use aravis::prelude::*;
use aravis::{AcquisitionMode, Aravis, Buffer, BufferStatus, Camera, PixelFormat};
use iceoryx2::prelude::*;
use ipc_types::rig_node::rig_node;
use ipc_types::{FrameHeader, monotonic_now_ns};

use crate::live_stats::LiveStats;

/// Buffers Aravis fills ahead of us.
const BUFFERS: usize = 4;

/// Capture from the GenICam camera `id` ("first": the first found) at
/// `width × height` and `fps`, publishing on `prefix` until SIGINT,
/// SIGTERM or `duration`.
pub fn run_genicam(
    prefix: &str,
    id: &str,
    (width, height): (u32, u32),
    fps: f64,
    duration: Option<Duration>,
) -> anyhow::Result<LiveStats> {
    let aravis = Aravis::initialize().map_err(|e| anyhow::anyhow!("GenICam: {e}"))?;
    if id.starts_with("Fake") {
        // SAFETY: a constant NUL-terminated name; Aravis copies it.
        #[allow(unsafe_code)]
        unsafe {
            aravis_sys::arv_enable_interface(c"Fake".as_ptr());
        }
    }
    let devices = aravis.get_device_list();
    let found: Vec<String> = devices.iter().map(|d| d.id.to_string_lossy().into_owned()).collect();
    let name = if id == "first" { found.first().cloned() } else { found.iter().find(|f| *f == id).cloned() };
    let Some(name) = name else {
        anyhow::bail!(
            "GenICam camera {id:?} not found; Aravis sees {}",
            if found.is_empty() { "none".to_owned() } else { found.join(", ") }
        );
    };
    let fail = |what: &str, e: aravis::glib::Error| anyhow::anyhow!("GenICam camera {name}: {what}: {e}");
    let cam = Camera::new(Some(&name)).map_err(|e| fail("opening", e))?;
    cam.set_pixel_format(PixelFormat::MONO_8).map_err(|e| fail("Mono8", e))?;
    cam.set_region(0, 0, width as i32, height as i32).map_err(|e| fail("region", e))?;
    let region = cam.region().map_err(|e| fail("reading the region", e))?;
    if region.2 != width as i32 || region.3 != height as i32 {
        anyhow::bail!(
            "GenICam camera {name}: gives {}×{}, not the calibration's {width}×{height}",
            region.2,
            region.3
        );
    }
    cam.set_acquisition_mode(AcquisitionMode::Continuous).map_err(|e| fail("continuous mode", e))?;
    if cam.is_frame_rate_available().unwrap_or(false) {
        // A camera that cannot do the rate keeps its own; the stamps tell.
        let _ = cam.set_frame_rate(fps);
    }
    let payload = cam.payload().map_err(|e| fail("payload size", e))? as usize;
    let stream = cam.create_stream().map_err(|e| fail("stream", e))?;
    for _ in 0..BUFFERS {
        stream.push_buffer(Buffer::new_allocate(payload));
    }
    let node = rig_node(prefix, None, SignalHandlingMode::HandleTerminationRequests)?;
    let mut out = crate::run::FrameOut::open(&node, (width * height) as usize)?;
    cam.start_acquisition().map_err(|e| fail("starting acquisition", e))?;
    let end = duration.map(|d| monotonic_now_ns() + d.as_nanos() as u64);
    let mut stats = LiveStats::default();
    let mut last_id: Option<u64> = None;
    let frame_bytes = (width * height) as usize;
    while end.is_none_or(|e| monotonic_now_ns() < e) && node.wait(Duration::ZERO).is_ok() {
        let Some(buffer) = stream.timeout_pop_buffer(200_000) else { continue };
        let received = monotonic_now_ns();
        let (data, len) = buffer.data();
        let whole = buffer.status() == BufferStatus::Success
            && buffer.image_pixel_format() == PixelFormat::MONO_8
            && buffer.image_width() == width as i32
            && buffer.image_height() == height as i32
            && !data.is_null()
            && len >= frame_bytes;
        if whole {
            if let Some(last) = last_id {
                stats.dropped += buffer.frame_id().wrapping_sub(last).saturating_sub(1);
            }
            last_id = Some(buffer.frame_id());
            // SAFETY: Aravis's buffer owns `len` bytes at `data` until it is
            // pushed back below; nothing else writes it meanwhile.
            #[allow(unsafe_code)]
            let pixels = unsafe { std::slice::from_raw_parts(data, frame_bytes) };
            stats.published += 1;
            let header =
                FrameHeader { seq: stats.published, stamp_ns: received, ..FrameHeader::mono8(width, height) };
            let sent = out.publish(header, pixels);
            stream.push_buffer(buffer);
            sent?;
        } else {
            stats.bad_buffers += 1;
            stream.push_buffer(buffer);
        }
    }
    let _ = cam.stop_acquisition();
    Ok(stats)
}
