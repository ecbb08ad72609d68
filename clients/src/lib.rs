//! UPM user-facing processes: the `upm` command line, vision and planner
//! clients. Binaries in `src/bin` are thin wrappers over this library.

pub mod cli;
pub mod solve_json;
pub mod validate;
