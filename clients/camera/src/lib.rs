//! `upm-camera`: frame sources. Each publishes camera frames
//! ([`ipc_types::FrameHeader`] over `[u8]` pixels on `upm/camera/frame`)
//! for `upm-vision`. The rendered camera may read the simulator's ground
//! truth; vision never does when it works from frames.

pub mod args;
pub mod board;
pub mod config;
pub mod files;
pub mod live;
#[cfg(feature = "genicam")]
mod live_genicam;
mod live_stats;
#[cfg(feature = "v4l2")]
mod live_v4l2;
pub mod render;
pub mod run;

pub use board::Board;
pub use config::{CameraSection, ClassLook};
pub use render::Renderer;
pub use run::FrameOut;
