//! The camera path inside one process, for the lock-step loop: the
//! simulator's truth drawn by the rendered camera (`[camera]`), then
//! vision's pipeline (segmentation, detection through the calibration
//! `upm calibrate camera` finds from the rendered board, tracker) exactly
//! as the processes of `upm run --camera rendered` do it, so the loop is
//! tested through images and stays bit-identical for a seed.

use ipc_types::PartStates;
use upm_camera::Renderer;
use upm_vision::detect::BlobCounts;
use upm_vision::part_states;
use upm_vision::pipeline::FramePipeline;

use crate::config::Config;

#[derive(Debug)]
pub struct RenderedSight {
    renderer: Renderer,
    vision: FramePipeline,
    /// Frames vision skipped (too dark, saturated, noise).
    pub bad_frames: u64,
}

impl RenderedSight {
    pub fn new(config: &Config) -> anyhow::Result<Self> {
        let (cal, _) = crate::calibrate_camera::from_rendered(&config.camera, config.plate.half_extent)?;
        config.vision.validate().map_err(anyhow::Error::msg)?;
        config.vision.validate_frames().map_err(anyhow::Error::msg)?;
        Ok(Self {
            vision: FramePipeline::new(&cal, &config.vision),
            renderer: Renderer::new(&config.camera).map_err(anyhow::Error::msg)?,
            bad_frames: 0,
        })
    }

    /// Blobs of every frame so far.
    pub fn counts(&self) -> BlobCounts {
        self.vision.counts
    }

    /// One frame of `truth`, `dt` s after the last: the parts as vision
    /// reports them (its own ids) into `out`.
    pub fn see(&mut self, truth: &PartStates, dt: f64, out: &mut PartStates) {
        let pixels = self.renderer.render(truth);
        let (w, h) = (self.vision.model().width, self.vision.model().height);
        if self.vision.process(pixels, w, h, w as usize, dt).is_err() {
            self.bad_frames += 1;
            self.vision.no_frame(dt);
        }
        part_states(self.vision.tracks(), truth.seq, truth.stamp_ns, out);
    }
}
