//! Live cameras as frame sources. Each backend sits behind a cargo feature:
//! `v4l2` (USB/UVC cameras through the kernel's V4L2 API; on by default,
//! it needs no system library) and `genicam` (GigE Vision and USB3 Vision
//! cameras through Aravis; off by default, it links the system's
//! `libaravis-0.8`). A build without a backend says so in one line.

use std::path::Path;
use std::time::Duration;

pub use crate::live_stats::LiveStats;

/// The V4L2 camera at `device`, `size` = the calibration's (width, height).
pub fn v4l2(
    prefix: &str,
    device: &Path,
    size: (u32, u32),
    fps: f64,
    duration: Option<Duration>,
) -> anyhow::Result<LiveStats> {
    #[cfg(feature = "v4l2")]
    return crate::live_v4l2::run_v4l2(prefix, device, size, fps, duration);
    #[cfg(not(feature = "v4l2"))]
    {
        let _ = (prefix, size, fps, duration);
        anyhow::bail!("{}: this upm-camera was built without the `v4l2` feature", device.display())
    }
}

/// The GenICam camera `id` ("first": the first one Aravis finds).
pub fn genicam(
    prefix: &str,
    id: &str,
    size: (u32, u32),
    fps: f64,
    duration: Option<Duration>,
) -> anyhow::Result<LiveStats> {
    #[cfg(feature = "genicam")]
    return crate::live_genicam::run_genicam(prefix, id, size, fps, duration);
    #[cfg(not(feature = "genicam"))]
    {
        let _ = (prefix, size, fps, duration);
        anyhow::bail!(
            "GenICam camera {id:?}: this upm-camera was built without the `genicam` feature \
             (cargo build --release -p upm-camera --features genicam, with libaravis-dev installed)"
        )
    }
}
