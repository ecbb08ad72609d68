//! One camera frame through vision's image pipeline: segmentation,
//! detection through the calibration, tracker. The frame loop of
//! `upm-vision`, the lock-step loop through rendered frames and `upm bench
//! vision` all run this one, so what they measure is what the rig does.

use crate::blobs::{BadFrame, SegmentParams, Segmenter};
use crate::calibration::Calibration;
use crate::detect::{BlobCounts, detect, split_area_px};
use crate::lens::CameraModel;
use crate::part_look::PartLook;
use crate::{Detection, Track, Tracker, VisionSection};

#[derive(Debug)]
pub struct FramePipeline {
    model: CameraModel,
    looks: Vec<PartLook>,
    segmenter: Segmenter,
    tracker: Tracker,
    found: Vec<Detection>,
    /// Blobs of every frame so far: detected, split, merged, cut, small.
    pub counts: BlobCounts,
}

impl FramePipeline {
    /// Allocates every buffer (the region of interest costs one
    /// unprojection per pixel); a frame then allocates nothing.
    pub fn new(cal: &Calibration, params: &VisionSection) -> Self {
        let segment = SegmentParams {
            threshold: params.threshold,
            split_above_px: split_area_px(&cal.camera, &params.classes),
            ..SegmentParams::default()
        };
        Self {
            model: cal.camera,
            looks: params.classes.clone(),
            segmenter: Segmenter::new(&cal.camera, cal.plate_half_extent, params.roi_margin, segment),
            tracker: Tracker::new(params),
            found: Vec::with_capacity(4 * ipc_types::MAX_PARTS),
            counts: BlobCounts::default(),
        }
    }

    /// One frame, `dt` s after the last: its detections, then the tracks.
    /// A bad frame leaves the tracker as it was.
    pub fn process(
        &mut self,
        pixels: &[u8],
        width: u32,
        height: u32,
        stride: usize,
        dt: f64,
    ) -> Result<(), BadFrame> {
        self.found.clear();
        let blobs = self.segmenter.segment(pixels, width, height, stride)?;
        detect(blobs, &self.model, &self.looks, &mut self.found, &mut self.counts);
        self.tracker.update(&self.found, dt);
        Ok(())
    }

    /// No frame (or a bad one) this period: the tracks age by `dt`.
    pub fn no_frame(&mut self, dt: f64) {
        self.found.clear();
        self.tracker.update(&self.found, dt);
    }

    /// The last good frame's detections.
    pub fn detections(&self) -> &[Detection] {
        &self.found
    }

    pub fn tracks(&self) -> &[Track] {
        self.tracker.tracks()
    }

    pub fn model(&self) -> &CameraModel {
        &self.model
    }

    /// The region of interest: columns `[start, end)` of each row.
    pub fn roi_spans(&self) -> &[(u32, u32)] {
        self.segmenter.roi_spans()
    }
}
