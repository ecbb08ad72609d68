//! Fixed capacities of the payloads and the error of a full payload.

use core::fmt;

/// Parts per [`crate::PartStates`] / entries per [`crate::ForceRequest`].
pub const MAX_PARTS: usize = 64;
/// Curl constraints per [`crate::ForceRequest`] (the solver's limit).
pub const MAX_CURLS: usize = 16;
/// Slots per [`crate::ExplicitSchedule`] and [`crate::Schedule`].
pub const MAX_SLOTS: usize = 192;
/// Largest number of configured rotation centers (the solver's limit).
pub const MAX_CENTERS: usize = 192;

/// A `push` did not fit in the fixed capacity of a payload.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CapacityError {
    /// All `capacity` entries are used (or `count` is corrupt and beyond it).
    Full { capacity: usize },
    /// The entry carries a curl but `capacity` curls are already set.
    CurlsFull { capacity: usize },
}

impl fmt::Display for CapacityError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Full { capacity } => write!(f, "payload is full ({capacity} entries)"),
            Self::CurlsFull { capacity } => write!(f, "payload already has {capacity} curls"),
        }
    }
}

impl core::error::Error for CapacityError {}
