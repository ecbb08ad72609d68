//! The wire under the MainDevice: whatever carries an EtherCAT frame to the
//! chain and back (a NIC's raw socket, a veth pair, or a simulated chain in
//! process).

use core::fmt;

/// The largest Ethernet frame (without FCS) a wire must carry.
pub const MAX_FRAME: usize = 1514;

/// Why a frame did not come back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WireError {
    /// Nothing answered within the wire's deadline.
    Lost,
    /// The wire refused or mangled the frame (wrong length, not EtherCAT).
    Refused,
    /// The operating system failed the send or the receive (errno).
    Io(i32),
}

impl fmt::Display for WireError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Lost => f.write_str("ethercat wire: no answer within the deadline"),
            Self::Refused => f.write_str("ethercat wire: frame refused"),
            Self::Io(errno) => write!(f, "ethercat wire: os error {errno}"),
        }
    }
}

impl core::error::Error for WireError {}

/// Carries one frame out and its answer back, in place: an EtherCAT chain
/// answers a frame with the same frame, datagrams filled in. Called on the
/// motor thread at run time: implementations must not allocate, lock or
/// log, and must return by their deadline.
pub trait Wire: Send + 'static {
    fn round_trip(&mut self, frame: &mut [u8]) -> Result<(), WireError>;
}
