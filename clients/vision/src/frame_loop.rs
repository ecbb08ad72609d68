//! Vision from camera frames: each frame on `upm/camera/frame` is checked,
//! segmented, its blobs turned into detections through the calibration,
//! tracked, and published as `PartStates` stamped with the frame's
//! exposure. A bad frame (header, size, too dark, saturated, noise) is
//! counted and skipped; the loop never stalls on one. It sleeps on the
//! frame event, so a source that notifies is served at once; one that does
//! not is read at the next poll (every millisecond).

use std::path::Path;
use std::time::{Duration, Instant};

use ipc_types::wake_event::{WakeEvent, wake_listener};
use ipc_types::{PartState, monotonic_now_ns};
use serde::Serialize;

use crate::VisionSection;
use crate::blobs::BadFrame;
use crate::calibration::Calibration;
use crate::outputs::Outputs;
use crate::pipeline::FramePipeline;

/// What vision did with the frames it received (`--stats FILE`, JSON).
#[derive(Debug, Clone, Default, Serialize)]
pub struct FrameStats {
    pub frames: u64,
    pub published: u64,
    /// Frames whose header disagreed with the payload or the calibration.
    pub bad_header: u64,
    pub too_dark: u64,
    pub saturated: u64,
    pub too_many_runs: u64,
    pub wrong_size: u64,
    pub detected: u64,
    pub merged_blobs: u64,
    pub cut_blobs: u64,
    pub small_blobs: u64,
    /// Detections that were one of two touching parts, split.
    pub split_detections: u64,
    /// Frame received → PartStates published, µs.
    pub processing_p50_us: f64,
    pub processing_p99_us: f64,
    pub processing_max_us: f64,
    /// Frame stamp (middle of the exposure) → PartStates published, µs:
    /// the camera's own delay and transport included.
    pub frame_age_p50_us: f64,
    pub frame_age_p99_us: f64,
}

/// Keeps the last processing times without allocating per frame.
struct Times {
    us: Vec<f64>,
    next: usize,
}

impl Times {
    const CAPACITY: usize = 1 << 14;

    fn push(&mut self, us: f64) {
        if self.us.len() < Self::CAPACITY {
            self.us.push(us);
        } else {
            self.us[self.next] = us;
            self.next = (self.next + 1) % Self::CAPACITY;
        }
    }

    /// p50, p99 and max (0 without samples).
    fn percentiles(&self) -> [f64; 3] {
        let mut v = self.us.clone();
        v.sort_by(f64::total_cmp);
        let at = |q: f64| upm_stats::percentile(&v, q);
        [at(0.5), at(0.99), at(1.0)].map(|x| x.unwrap_or(0.0))
    }
}

/// Longest sleep between looks for frames (a source that does not notify).
const POLL: Duration = Duration::from_millis(1);

/// Run vision on camera frames on `prefix` until SIGINT/SIGTERM (or
/// `duration`).
pub fn run_frames(
    prefix: &str,
    params: &VisionSection,
    duration: Option<Duration>,
) -> anyhow::Result<FrameStats> {
    let cal = Calibration::load(Path::new(&params.calibration)).map_err(anyhow::Error::msg)?;
    let (width, height) = (cal.camera.width, cal.camera.height);
    // The core refuses every message with an outline wider than the plate.
    let extent = ipc_types::ValidationLimits::new(cal.plate_half_extent, 0).max_part_extent();
    for (i, look) in params.classes.iter().enumerate() {
        if let Err(e) = look.outline().put_on(PartState::ZERO).check_shape(extent) {
            anyhow::bail!("vision.classes[{i}].radius_mm {}: {e}", look.radius * 1e3);
        }
    }
    let mut pipeline = FramePipeline::new(&cal, params);
    let mut out = Outputs::open(prefix)?;
    let frames = ipc_types::ports::frame_subscriber(out.node())?;
    let woken = wake_listener(out.node(), WakeEvent::Frame)?;
    let end = duration.map(|d| monotonic_now_ns() + d.as_nanos() as u64);
    let mut stats = FrameStats::default();
    let mut times = Times { us: Vec::with_capacity(Times::CAPACITY), next: 0 };
    let mut ages = Times { us: Vec::with_capacity(Times::CAPACITY), next: 0 };
    let mut last_complaint: Option<Instant> = None;
    loop {
        while let Some(frame) = frames.receive().map_err(|e| anyhow::anyhow!("receiving a frame: {e:?}"))? {
            let started = Instant::now();
            stats.frames += 1;
            let h = *frame.user_header();
            let pixels = frame.payload();
            let complaint = match h.check(pixels.len(), width, height) {
                Err(e) => {
                    stats.bad_header += 1;
                    Some(e.to_string())
                }
                Ok(()) => {
                    match pipeline.process(pixels, h.width, h.height, h.stride as usize, out.dt(h.stamp_ns)) {
                        Err(bad) => {
                            *match bad {
                                BadFrame::TooDark => &mut stats.too_dark,
                                BadFrame::TooBright => &mut stats.saturated,
                                BadFrame::TooManyRuns => &mut stats.too_many_runs,
                                BadFrame::WrongSize => &mut stats.wrong_size,
                            } += 1;
                            Some(format!("frame {}: {bad}", h.seq))
                        }
                        Ok(()) => {
                            stats.published += 1;
                            out.publish(pipeline.tracks(), stats.published, h.stamp_ns)?;
                            ages.push(monotonic_now_ns().saturating_sub(h.stamp_ns) as f64 / 1e3);
                            None
                        }
                    }
                }
            };
            if let Some(text) = complaint
                && last_complaint.is_none_or(|t| t.elapsed() > Duration::from_secs(1))
            {
                // At most one line a second; the counts have them all.
                eprintln!("upm-vision: skipped a frame: {text}");
                last_complaint = Some(Instant::now());
            }
            times.push(started.elapsed().as_secs_f64() * 1e6);
        }
        if end.is_some_and(|e| monotonic_now_ns() >= e) || !out.wait(Duration::ZERO) {
            break;
        }
        match woken.timed_wait(|_| {}, POLL) {
            Ok(_) => {}
            // SIGINT/SIGTERM while asleep: stop as the node's wait would,
            // with the statistics written.
            Err(iceoryx2::port::listener::ListenerWaitError::InterruptSignal) => break,
            Err(e) => anyhow::bail!("waiting for a frame: {e:?}"),
        }
    }
    let counts = pipeline.counts;
    stats.detected = counts.detected;
    stats.merged_blobs = counts.merged;
    stats.cut_blobs = counts.cut;
    stats.small_blobs = counts.small;
    stats.split_detections = counts.split;
    [stats.processing_p50_us, stats.processing_p99_us, stats.processing_max_us] = times.percentiles();
    [stats.frame_age_p50_us, stats.frame_age_p99_us, _] = ages.percentiles();
    Ok(stats)
}
