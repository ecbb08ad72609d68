//! The rate vision publishes part states at, as every process reads it:
//! vision and the camera default to it, and the core announces it
//! (`RigInfo.vision_frame_hz`) from the same file without linking them.

/// `[vision] frame_hz` and `[camera] frame_hz` when the file gives none.
pub const DEFAULT_FRAME_HZ: f64 = 30.0;

/// `[vision] source` when vision reads camera frames (at the camera's
/// `frame_hz`) instead of the simulator's ground truth (at its own).
pub const FRAMES_SOURCE: &str = "frames";

/// The rate vision publishes at: the camera's when vision reads camera
/// frames (`source` is [`FRAMES_SOURCE`]), else vision's own.
pub fn publish_hz(source: &str, vision_hz: f64, camera_hz: f64) -> f64 {
    if source == FRAMES_SOURCE { camera_hz } else { vision_hz }
}
