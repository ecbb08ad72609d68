//! What `upm`'s commands do: the rig's configuration and scenarios, the
//! launcher of the closed loop, recording and replay, status, soak and the
//! calibrate commands. The command tree itself is `upm-cli`; the benches
//! are `upm-bench`; `solve` and `validate` are `upm-paper`.

pub mod calibrate_camera;
pub mod calibrate_plate;
pub mod closed_loop;
pub mod config;
pub mod cpu_load;
pub mod die_with_parent;
pub mod exit;
pub mod feed_metrics;
pub mod input;
pub mod launcher;
pub mod recording;
pub mod rendered_sight;
pub mod replay;
pub mod scenario;
pub mod soak;
pub mod status;
pub mod truth_sight;
