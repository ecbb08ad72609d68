//! Image files as a frame source: the PNG files of a directory, in name
//! order, published at a rate (a recorded session replayed, or a camera
//! nobody here wrote). Colour images are converted to mono8. A file that
//! does not decode, or whose size differs from the first frame's, is
//! counted and skipped with at most one line a second; nothing panics.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use iceoryx2::node::NodeWaitFailure;
use iceoryx2::prelude::*;
use ipc_types::rig_node::rig_node;
use ipc_types::{FrameHeader, monotonic_now_ns};

/// What a file replay did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FileStats {
    pub published: u64,
    pub unreadable: u64,
    pub wrong_size: u64,
}

impl core::fmt::Display for FileStats {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "{} frames published, {} files unreadable, {} of another size",
            self.published, self.unreadable, self.wrong_size
        )
    }
}

/// The `*.png` files of `dir`, in name order.
pub fn png_files(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| anyhow::anyhow!("reading {}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("png")))
        .collect();
    files.sort();
    if files.is_empty() {
        anyhow::bail!("{}: no .png files", dir.display());
    }
    Ok(files)
}

/// Publish the PNG files of `dir` at `rate_hz` on `prefix` (from the
/// start again with `looping`) until done, SIGINT/SIGTERM or `duration`.
pub fn run_files(
    prefix: &str,
    dir: &Path,
    rate_hz: f64,
    looping: bool,
    duration: Option<Duration>,
) -> anyhow::Result<FileStats> {
    if !(rate_hz.is_finite() && rate_hz > 0.0 && rate_hz <= 1000.0) {
        anyhow::bail!("--rate must be in (0, 1000] Hz, got {rate_hz}");
    }
    let files = png_files(dir)?;
    let mut stats = FileStats::default();
    let mut complained: Option<Instant> = None;
    let mut complain = |text: String| {
        if complained.is_none_or(|t| t.elapsed() > Duration::from_secs(1)) {
            eprintln!("upm-camera: skipped {text}");
            complained = Some(Instant::now());
        }
    };
    // The first frame that decodes sets the size for the whole replay.
    let decode = |p: &Path| image::open(p).map(|i| i.to_luma8());
    let (width, height) = files
        .iter()
        .find_map(|p| decode(p).ok().map(|i| i.dimensions()))
        .ok_or_else(|| anyhow::anyhow!("{}: no .png file decodes", dir.display()))?;
    let node = rig_node(prefix, None, SignalHandlingMode::HandleTerminationRequests)?;
    let mut frames = crate::run::FrameOut::open(&node, (width * height) as usize)?;
    let period = Duration::from_secs_f64(1.0 / rate_hz);
    let end = duration.map(|d| Instant::now() + d);
    let mut next = Instant::now();
    for path in files.iter().cycle().take(if looping { usize::MAX } else { files.len() }) {
        let img = match decode(path) {
            Ok(img) if img.dimensions() == (width, height) => img,
            Ok(img) => {
                stats.wrong_size += 1;
                let (w, h) = img.dimensions();
                complain(format!("{}: {w} × {h}, the replay is {width} × {height}", path.display()));
                continue;
            }
            Err(e) => {
                stats.unreadable += 1;
                complain(format!("{}: {e}", path.display()));
                continue;
            }
        };
        let wait = next.saturating_duration_since(Instant::now());
        if end.is_some_and(|e| Instant::now() + wait >= e) {
            break;
        }
        match node.wait(wait) {
            Ok(()) => {}
            Err(NodeWaitFailure::Interrupt | NodeWaitFailure::TerminationRequest) => break,
        }
        next = (next + period).max(Instant::now());
        stats.published += 1;
        let header = FrameHeader {
            seq: stats.published,
            stamp_ns: monotonic_now_ns(),
            ..FrameHeader::mono8(width, height)
        };
        frames.publish(header, img.as_raw())?;
    }
    Ok(stats)
}
