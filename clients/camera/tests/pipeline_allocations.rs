//! Vision's per-frame work allocates nothing after warm-up: segmentation,
//! coverage moments, pair splitting, detection through the calibration and
//! the tracker, on rendered frames of moving, touching and turning parts,
//! counted by the same allocator the core's binaries install.

use ipc_types::{PartState, PartStates};
use rt_core::{RtAllocCounter, alloc_count};
use upm_camera::CameraSection;
use upm_camera::Renderer;
use upm_vision::VisionSection;
use upm_vision::calibration::Calibration;
use upm_vision::class_outline::ClassOutline;
use upm_vision::pipeline::FramePipeline;

#[global_allocator]
static ALLOC: RtAllocCounter = RtAllocCounter;

#[test]
fn a_frame_allocates_nothing_after_warm_up() {
    let mut cam = CameraSection::default();
    cam.classes[1].shape = ClassOutline::Square;
    cam.classes[1].radius = 0.017;
    let model = cam.model().expect("model");
    let params = VisionSection { classes: cam.vision_classes(), ..VisionSection::default() };
    let cal = Calibration { plate_half_extent: cam.half_extent, camera: model };
    let mut vision = FramePipeline::new(&cal, &params);
    let mut renderer = Renderer::new(&cam).expect("renderer");
    // Parts moving and turning; two of them touching; one over the edge.
    let frame = |k: usize| {
        let t = k as f64 / 30.0;
        let mut s = PartStates::new();
        for i in 0..12u32 {
            let x = -0.8 + 0.14 * f64::from(i) + 0.02 * t;
            let _ = s.push(PartState::new(i, i % 2, 0, [x, 0.1, 0.5 * t], [0.02, 0.0, 0.5]));
        }
        let _ = s.push(PartState::new(20, 0, 0, [0.3, -0.3, 0.0], [0.0; 3]));
        let _ = s.push(PartState::new(21, 0, 0, [0.33, -0.3, 0.0], [0.0; 3]));
        let _ = s.push(PartState::new(22, 1, 0, [0.998, 0.2, 0.0], [0.0; 3]));
        s
    };
    let (w, h) = (model.width, model.height);
    let mut frames = Vec::new();
    for k in 0..24 {
        frames.push(renderer.render(&frame(k)).to_vec());
    }
    for f in &frames[..4] {
        vision.process(f, w, h, w as usize, 1.0 / 30.0).expect("a good frame");
    }
    let ((), allocations) = alloc_count::allocations_in(|| {
        for f in &frames[4..] {
            vision.process(f, w, h, w as usize, 1.0 / 30.0).expect("a good frame");
        }
        vision.no_frame(1.0 / 30.0);
    });
    assert!(vision.counts.detected >= 20 * 12, "{:?}", vision.counts);
    assert!(vision.counts.split > 0 && vision.counts.cut > 0, "{:?}", vision.counts);
    assert_eq!(allocations, 0, "allocations in 20 frames after warm-up");
}
