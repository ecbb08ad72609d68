//! UPM user-facing processes: the `upm` command line, vision and planner
//! clients. Binaries in `src/bin` are thin wrappers over this library.

pub mod bench_ipc;
pub mod bench_latency;
pub mod bench_solver;
pub mod bounded_reference;
pub mod cli;
pub mod closed_loop;
pub mod config;
pub mod core_process;
pub mod core_watch;
pub mod cpu_load;
pub mod die_with_parent;
pub mod feeder;
pub mod host_facts;
pub mod launcher;
pub mod planner;
pub mod scenario;
pub mod soak;
pub mod solve_json;
pub mod status;
pub mod validate;
pub mod vision;
