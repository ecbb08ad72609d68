//! The `upm` command line: configuration, the launcher of the closed loop,
//! status, plots and benchmarks. `upm run` starts the RT core's own binary
//! (`upm-core`) and each client's (`upm-vision`, `upm-planner`,
//! `upm-camera`, `upm-recorder`), or the client's hidden subcommand of
//! `upm` (`upm vision|planner|camera|recorder`) where its binary is not
//! built.

pub mod bench_calibration;
pub mod bench_ethercat;
pub mod bench_fidelity;
pub mod bench_fidelity_loop;
pub mod bench_ipc;
pub mod bench_latency;
pub mod bench_least_squares;
pub mod bench_planner_wake;
pub mod bench_record;
pub mod bench_solver;
pub mod bench_solver_shapes;
pub mod bench_sort;
pub mod bench_vision;
pub mod bench_vision_latency;
pub mod bounded_reference;
pub mod calibrate_camera;
pub mod calibrate_plate;
pub mod cli;
pub mod closed_loop;
pub mod config;
pub mod cpu_load;
pub mod die_with_parent;
pub mod faer_reference;
pub mod feeder;
pub mod host_facts;
pub mod launcher;
pub mod recording;
pub mod rendered_sight;
pub mod replay;
pub mod scenario;
pub mod soak;
pub mod solve_json;
pub mod status;
pub mod truth_sight;
pub mod validate;
