//! `upm bench`: every figure in BENCHMARKS.md, each beside its reference
//! measured in the same run (cyclictest, DAQP's speed, faer, nalgebra,
//! Clarabel, raw iceoryx2, the feeders' shake-and-pick).

pub mod bench_calibration;
pub mod bench_ethercat;
pub mod bench_feed;
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
pub mod faer_reference;
pub mod feeder;
pub mod host_facts;
pub mod ipc_probe;
pub mod solver_case;
pub mod two_at_a_time;
