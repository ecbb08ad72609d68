//! A message as the bytes that cross shared memory, and back: what a
//! recorder stores and a replay reads. Every payload is `#[repr(C)]` with
//! only integer and float fields and no padding (each type asserts its size
//! field by field), so every byte is initialised and every byte pattern of
//! the right length is a valid value.

#![allow(unsafe_code)]

use core::fmt;

use iceoryx2::prelude::ZeroCopySend;

use crate::{
    CoreCommand, ExplicitSchedule, FeedStatus, ForceRequest, FrameHeader, LineStatus, PartStates,
    PickCommand, RecipeCommand, Rejection, RigInfo, Schedule, Telemetry, service_names,
};

/// Why bytes are not a message of the asked type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WrongLength {
    pub type_name: &'static str,
    pub expected: usize,
    pub found: usize,
}

impl fmt::Display for WrongLength {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} is {} bytes, found {}", self.type_name, self.expected, self.found)
    }
}

impl core::error::Error for WrongLength {}

mod sealed {
    pub trait Sealed {}
}

/// A payload of the protocol: its bytes, its iceoryx2 type name and the
/// service it travels on. Implemented for the protocol's messages only.
pub trait WireMessage: ZeroCopySend + Copy + sealed::Sealed + 'static {
    /// The service this payload is published on.
    const SERVICE: &'static str;

    /// The iceoryx2 type name, e.g. `upm::PartStates.v6`.
    fn wire_type_name() -> &'static str {
        // SAFETY: only reads the name the derive generated.
        unsafe { <Self as ZeroCopySend>::type_name() }
    }

    /// The message's bytes, exactly as in shared memory.
    fn as_bytes(&self) -> &[u8] {
        // SAFETY: `Self` is repr(C) without padding (sealed to the
        // protocol's types, each asserting its size), so all
        // size_of::<Self>() bytes are initialised.
        unsafe { core::slice::from_raw_parts((self as *const Self).cast::<u8>(), size_of::<Self>()) }
    }

    /// The message whose bytes are `bytes` (any content, exact length).
    fn from_bytes(bytes: &[u8]) -> Result<Self, WrongLength> {
        if bytes.len() != size_of::<Self>() {
            return Err(WrongLength {
                type_name: Self::wire_type_name(),
                expected: size_of::<Self>(),
                found: bytes.len(),
            });
        }
        // SAFETY: the length is exact and every bit pattern is a valid
        // `Self` (integer and float fields only); the read is unaligned.
        Ok(unsafe { core::ptr::read_unaligned(bytes.as_ptr().cast::<Self>()) })
    }
}

macro_rules! wire_message {
    ($($t:ty => $service:expr),* $(,)?) => {$(
        impl sealed::Sealed for $t {}
        impl WireMessage for $t {
            const SERVICE: &'static str = $service;
        }
    )*};
}

wire_message!(
    PartStates => service_names::PART_STATES,
    ForceRequest => service_names::FORCE_REQUEST,
    ExplicitSchedule => service_names::EXPLICIT_SCHEDULE,
    CoreCommand => service_names::CORE_COMMAND,
    Schedule => service_names::SCHEDULE,
    Telemetry => service_names::TELEMETRY,
    Rejection => service_names::REJECTION,
    RigInfo => service_names::RIG_INFO,
    FeedStatus => service_names::FEED,
    PickCommand => service_names::PICK,
    RecipeCommand => service_names::RECIPE,
    LineStatus => service_names::LINE,
    FrameHeader => service_names::CAMERA_FRAME,
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_round_trip_and_a_wrong_length_is_named() {
        let mut m = Schedule::new();
        m.seq = 7;
        m.parts_seq = 3;
        let back = Schedule::from_bytes(m.as_bytes()).expect("exact length");
        assert_eq!(back, m);
        let e = PartStates::from_bytes(&[0; 3]).expect_err("3 bytes");
        assert_eq!(e.found, 3);
        assert!(e.to_string().starts_with("upm::PartStates.v6 is "), "{e}");
    }

    #[test]
    fn outlines_round_trip_and_v4_bytes_are_refused() {
        use crate::{PartState, SHAPE_POLYGON};
        let tri = [[0.02, 0.0], [-0.01, 0.015], [-0.01, -0.015]];
        let mut m = PartStates::new();
        m.push(PartState::new(1, 0, 0, [0.1, 0.0, 0.5], [0.0; 3]).with_polygon(&tri).expect("3 fit"))
            .expect("fits");
        m.push(PartState::new(2, 0, 0, [0.0, 0.1, 0.0], [0.0; 3]).with_disc(0.02)).expect("fits");
        let bytes = m.as_bytes();
        // parts[0].shape sits at 24 + 12, where v4 had `reserved`.
        assert_eq!(bytes[36..40], SHAPE_POLYGON.to_ne_bytes());
        assert_eq!(PartStates::from_bytes(bytes), Ok(m));
        let e = PartStates::from_bytes(&[0; 4120]).expect_err("a v4 PartStates");
        assert_eq!(e.to_string(), "upm::PartStates.v6 is 13336 bytes, found 4120");
    }
}
