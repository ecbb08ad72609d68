//! Why the EtherCAT driver did not start: one line naming the device.

use core::fmt;

use crate::params::{ExpectedSubDevice, ParamsError};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartError {
    Params(ParamsError),
    /// The rig's actuator count differs from the drives configured.
    RigCount {
        rig: usize,
        drives: usize,
    },
    /// Bus scan, state change or ethercrab internals failed.
    Bus(ethercrab::error::Error),
    /// Fewer SubDevices answered than the rig expects.
    Missing {
        position: usize,
        expected: ExpectedSubDevice,
    },
    /// A SubDevice that is not the one expected at its position (or one
    /// more than expected).
    Unexpected {
        position: usize,
        vendor: u32,
        product: u32,
    },
    /// An SDO the driver writes at start-up failed.
    Sdo {
        position: usize,
        index: u16,
        error: ethercrab::error::Error,
    },
    /// The process image is not the one mapped (inputs, outputs in bytes).
    ProcessImage {
        position: usize,
        inputs: usize,
        outputs: usize,
    },
    /// A drive did not reach *operation enabled* in time.
    Enable {
        position: usize,
        statusword: u16,
    },
}

impl fmt::Display for StartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Params(e) => write!(f, "ethercat: {e}"),
            Self::RigCount { rig, drives } => {
                write!(f, "ethercat: the rig has {rig} actuators but {drives} drives are configured")
            }
            Self::Bus(e) => write!(f, "ethercat: bus start-up failed: {e}"),
            Self::Missing { position, expected } => write!(
                f,
                "ethercat: subdevice {position} (vendor {:#010x}, product {:#010x}) is missing: the bus ends before it",
                expected.vendor, expected.product
            ),
            Self::Unexpected { position, vendor, product } => write!(
                f,
                "ethercat: subdevice {position} is vendor {vendor:#010x} product {product:#010x}, not the drive configured there"
            ),
            Self::Sdo { position, index, error } => {
                write!(f, "ethercat: subdevice {position}: SDO {index:#06x} failed: {error}")
            }
            Self::ProcessImage { position, inputs, outputs } => write!(
                f,
                "ethercat: subdevice {position} maps {inputs} input and {outputs} output bytes, not the CiA 402 image (9, 13)"
            ),
            Self::Enable { position, statusword } => write!(
                f,
                "ethercat: drive {position} did not reach operation enabled (statusword {statusword:#06x})"
            ),
        }
    }
}

impl core::error::Error for StartError {}
