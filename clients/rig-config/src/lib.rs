//! The rig's one TOML file, as each process reads it: every process takes
//! the sections of its own concern ([`RigFile::section`]) and ignores the
//! rest; the `upm` CLI validates the whole file. Parsing has no side
//! effects: nothing here opens a port, spawns or touches shared memory.

mod error;
mod file;
pub mod frame_rate;
pub mod plate_calibration;
mod process_args;
mod service;
pub mod shared_table;

pub use error::ConfigError;
pub use file::{RigFile, load_toml, parse_toml};
pub use plate_calibration::{CalibrationSection, PlateCalibration};
pub use process_args::ProcessArgs;
pub use service::ServiceSection;
