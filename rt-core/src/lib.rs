//! UPM real-time core.
//!
//! `solver` turns desired per-part forces and curls into the rotation
//! intensities of one closed plate motion (Reznik & Canny 1998, §2–3).
//! Everything on the hot path is allocation-free after construction.

pub mod solver;

pub use solver::{
    CurlConstraint, ForceConstraint, LeastSquaresSystem, PartShape, Problem, Solution, SolveError,
    SolveMethod, Solver, SolverCapacity, SolverParams,
};

/// The driver boundary (read → update → write) every plate driver implements.
pub mod driver;
/// Closed plate motion: slot waveforms, limits, sampling, rig kinematics.
pub mod motion;
/// The RT process: motor loop, solver stage, wait-free hand-over, threads.
pub mod runtime;
