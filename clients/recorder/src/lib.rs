//! `upm-recorder`: the rig's flight recorder and live view (ARCHITECTURE.md
//! §3). A process of its own, never a thread of the core: it subscribes to
//! every service of a rig and writes one MCAP file per run (each message's
//! raw bytes for exact replay, a decoded JSON companion, a Foxglove scene
//! and the core's latency figures), and serves the same channels over
//! Foxglove's WebSocket protocol when asked (`upm monitor`).

pub mod args;
pub mod decoded;
pub mod recorder;
pub mod rig_log;
pub mod scene;
pub mod seq_gaps;

pub use recorder::{Recorder, RecorderOptions};
pub use rig_log::{
    CONFIG_ATTACHMENT, COUNTS_METADATA, JSON_SUFFIX, LATENCY_TOPIC, LogOptions, PROFILE, RAW_ENCODING,
    RUN_METADATA, RigLog, SCENE_TOPIC, segment_path,
};
pub use scene::PlateView;
