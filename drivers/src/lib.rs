//! Plate drivers for UPM: the embedded physics simulator (the default
//! driver), an ideal mock, the lock-step loop and the conformance suite every
//! [`rt_core::driver::PlateDriver`] runs.

pub mod conformance;
pub mod ideal;
pub mod lockstep;
pub mod rng;
pub mod sim;

pub use ideal::IdealDriver;
pub use sim::{
    ActuatorModel, PartSpec, PartState, Shape, SimConfig, SimConfigError, SimCounters, SimError, Simulator,
};
