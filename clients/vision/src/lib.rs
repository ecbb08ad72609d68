//! `upm-vision`: the camera client. Its only output is the public
//! `PartStates` service; it links `ipc-types` and what it computes with,
//! never the simulator. The default source is a simulated camera that reads
//! ground truth from its service (`upm/sim/ground_truth`, published by a
//! core that runs the simulator), adds noise, latency and dropped frames,
//! tracks parts without using the simulator's ids, and publishes
//! PartStates.

pub mod args;
pub mod blobs;
pub mod calibration;
pub mod camera;
pub mod class_outline;
pub mod config;
pub mod detect;
pub mod frame_loop;
pub mod lens;
pub mod outputs;
pub mod part_look;
pub mod pipeline;
pub mod run;
pub mod tracker;

pub use camera::Camera;
pub use class_outline::BodyOutline;
pub use config::VisionSection;
pub use outputs::part_states;
pub use part_look::PartLook;
pub use run::run;
pub use tracker::{Detection, Track, Tracker};
