//! SDO abort codes (CiA 301), as a CoE reply carries them.

pub const COMMAND_INVALID: u32 = 0x0504_0001;
pub const UNSUPPORTED_ACCESS: u32 = 0x0601_0000;
pub const READ_ONLY: u32 = 0x0601_0002;
pub const NO_OBJECT: u32 = 0x0602_0000;
pub const LENGTH_MISMATCH: u32 = 0x0607_0010;
pub const NO_SUBINDEX: u32 = 0x0609_0011;
pub const VALUE_INVALID: u32 = 0x0609_0030;
pub const VALUE_TOO_HIGH: u32 = 0x0609_0031;
pub const CANNOT_MAP: u32 = 0x0604_0041;
pub const DEVICE_STATE: u32 = 0x0800_0022;
