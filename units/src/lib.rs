//! Serde adapters between the rig file's units and the code's: a field
//! is declared once, on the type the code uses, in SI units, and its
//! `#[serde(with = …)]` names the unit the file writes it in.

pub mod cpu;
pub mod duration;
pub mod scaled;

pub use duration::{ms_as_ns, us_as_ns};
pub use scaled::{Scaled, deg, mm, ms_as_s};
