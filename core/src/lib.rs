//! The RT core process, `upm-core`: its config sections ([`config`]), the
//! driver `[driver]` names ([`plate_driver`]) and the process itself
//! ([`core_process`]) around rt-core's runtime. Nothing here links a
//! client's crate: vision, planner, camera and recorder are processes of
//! their own (ARCHITECTURE.md §8).

pub mod config;
pub mod core_process;
pub mod plate_driver;
pub mod recipe_changeover;
