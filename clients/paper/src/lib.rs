//! The paper's force problem as a command: `upm solve` reads a problem in
//! JSON and answers with the plate motion; `upm validate` plays that motion
//! on the simulator and measures the forces the parts feel.

pub mod solve_json;
pub mod validate;
