//! UPM's EtherCAT plate driver: one CiA 402 servo drive per actuator, in
//! cyclic synchronous position mode, through ethercrab's MainDevice.
//!
//! - [`EthercatDriver`]: the [`upm_hardware::PlateDriver`]; start-up
//!   checks every SubDevice against the rig's configuration, maps and
//!   configures the drives by SDO, brings the bus to OP and enables them;
//! - [`Wire`]: what carries frames (a simulated chain in process, a raw
//!   socket on a NIC or a veth pair);
//! - the frame pump: ethercrab's PDU loop driven on the calling thread, so
//!   an exchange is one poll on the motor thread.

// Index loops mirror the per-axis arrays.
#![allow(clippy::needless_range_loop)]

pub mod cia402_axis;
pub mod driver;
mod frame_pump;
pub mod params;
pub mod raw_socket;
pub mod start_error;
pub mod wire;

pub use driver::EthercatDriver;
pub use params::{EthercatParams, ExpectedSubDevice, ParamsError};
pub use raw_socket::{RawSocket, RawSocketWire};
pub use start_error::StartError;
pub use wire::{MAX_FRAME, Wire, WireError};
