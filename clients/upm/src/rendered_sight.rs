//! The camera path inside one process, for the lock-step loop: the
//! simulator's truth drawn by the rendered camera (`[camera]`), then
//! vision's pipeline (segmentation, detection through the calibration
//! `upm calibrate camera` finds from the rendered board, tracker) exactly
//! as the processes of `upm run --camera rendered` do it, so the loop is
//! tested through images and stays bit-identical for a seed.

use ipc_types::PartStates;
use upm_camera::Renderer;
use upm_vision::blobs::{SegmentParams, Segmenter};
use upm_vision::detect::{BlobCounts, PartLook, detect, split_area_px};
use upm_vision::lens::CameraModel;
use upm_vision::{Detection, Tracker, part_states};

use crate::config::Config;

#[derive(Debug)]
pub struct RenderedSight {
    renderer: Renderer,
    model: CameraModel,
    segmenter: Segmenter,
    looks: Vec<PartLook>,
    tracker: Tracker,
    found: Vec<Detection>,
    pub counts: BlobCounts,
    /// Frames vision skipped (too dark, saturated, noise).
    pub bad_frames: u64,
}

impl RenderedSight {
    pub fn new(config: &Config) -> anyhow::Result<Self> {
        let truth = config.camera.model().map_err(anyhow::Error::msg)?;
        let scene = config.camera.scene().map_err(anyhow::Error::msg)?;
        let (cal, _) = crate::calibrate_camera::from_rendered(&config.camera, config.plate.half_extent)?;
        let model = cal.camera;
        let frames = config.vision.frames_for_camera().map_err(anyhow::Error::msg)?;
        let (_, tracker) = config.vision.params().map_err(anyhow::Error::msg)?;
        Ok(Self {
            segmenter: Segmenter::new(
                &model,
                config.plate.half_extent,
                frames.roi_margin,
                SegmentParams { split_above_px: split_area_px(&model, &frames.looks), ..frames.segment },
            ),
            renderer: Renderer::new(truth, scene).map_err(anyhow::Error::msg)?,
            model,
            looks: frames.looks,
            tracker: Tracker::new(tracker),
            found: Vec::with_capacity(4 * ipc_types::MAX_PARTS),
            counts: BlobCounts::default(),
            bad_frames: 0,
        })
    }

    /// One frame of `truth`, `dt` s after the last: the parts as vision
    /// reports them (its own ids) into `out`.
    pub fn see(&mut self, truth: &PartStates, dt: f64, out: &mut PartStates) {
        let pixels = self.renderer.render(truth);
        self.found.clear();
        match self.segmenter.segment(pixels, self.model.width, self.model.height, self.model.width as usize) {
            Ok(blobs) => detect(blobs, &self.model, &self.looks, &mut self.found, &mut self.counts),
            Err(_) => self.bad_frames += 1,
        }
        self.tracker.update(&self.found, dt);
        part_states(self.tracker.tracks(), truth.seq, truth.stamp_ns, out);
    }
}
