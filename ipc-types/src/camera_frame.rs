//! Camera frames: frame source → vision, on `upm/camera/frame`. The pixels
//! are an iceoryx2 slice payload (`[u8]`, sized at start-up from the
//! camera's resolution) and this header is its user header, so a 4 MB
//! frame crosses processes without a copy. Anyone can write a frame source
//! against `ipc-types` alone, like a planner.

use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::PROTOCOL_VERSION;

/// Frame source → vision: what the pixels of one frame are.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::FrameHeader.v6"))]
pub struct FrameHeader {
    pub protocol_version: u32,
    /// [`FrameHeader::MONO8`] (one byte per pixel) is the only format.
    pub pixel_format: u32,
    pub width: u32,
    pub height: u32,
    /// Bytes from one row to the next, at least `width`.
    pub stride: u32,
    pub reserved: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns at the middle of the exposure.
    pub stamp_ns: u64,
    pub exposure_ns: u64,
}

const _: () = assert!(size_of::<FrameHeader>() == 6 * 4 + 3 * 8);

/// Why a frame was skipped. Vision counts these; nothing panics.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameError {
    WrongProtocolVersion {
        found: u32,
    },
    UnknownPixelFormat {
        found: u32,
    },
    Empty {
        width: u32,
        height: u32,
    },
    StrideTooSmall {
        stride: u32,
        width: u32,
    },
    /// `stride × height` is not the payload's length.
    LengthMismatch {
        expected: u64,
        payload: usize,
    },
    /// Larger than the receiver was started for.
    TooLarge {
        width: u32,
        height: u32,
        max_width: u32,
        max_height: u32,
    },
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::WrongProtocolVersion { found } => {
                write!(f, "camera_frame.protocol_version {found} is not this build's {PROTOCOL_VERSION}")
            }
            Self::UnknownPixelFormat { found } => {
                write!(f, "camera_frame.pixel_format {found} is unknown (0 = mono8)")
            }
            Self::Empty { width, height } => write!(f, "camera_frame.width × height is {width} × {height}"),
            Self::StrideTooSmall { stride, width } => {
                write!(f, "camera_frame.stride {stride} is less than width {width}")
            }
            Self::LengthMismatch { expected, payload } => {
                write!(f, "camera_frame: stride × height is {expected} bytes, the payload {payload}")
            }
            Self::TooLarge { width, height, max_width, max_height } => write!(
                f,
                "camera_frame.width × height {width} × {height} exceeds the {max_width} × {max_height} vision was started for"
            ),
        }
    }
}

impl core::error::Error for FrameError {}

impl FrameHeader {
    pub const MONO8: u32 = 0;

    /// A mono8 frame of `width × height` with rows packed (`stride = width`).
    pub const fn mono8(width: u32, height: u32) -> Self {
        Self {
            protocol_version: PROTOCOL_VERSION,
            pixel_format: Self::MONO8,
            width,
            height,
            stride: width,
            reserved: 0,
            seq: 0,
            stamp_ns: 0,
            exposure_ns: 0,
        }
    }

    /// Bytes of pixels this header describes (`stride × height`).
    pub const fn bytes(&self) -> u64 {
        self.stride as u64 * self.height as u64
    }

    /// Check the header against the payload it came with and the largest
    /// frame the receiver accepts; the first problem found.
    pub fn check(&self, payload_len: usize, max_width: u32, max_height: u32) -> Result<(), FrameError> {
        if self.protocol_version != PROTOCOL_VERSION {
            return Err(FrameError::WrongProtocolVersion { found: self.protocol_version });
        }
        if self.pixel_format != Self::MONO8 {
            return Err(FrameError::UnknownPixelFormat { found: self.pixel_format });
        }
        let (width, height) = (self.width, self.height);
        if width == 0 || height == 0 {
            return Err(FrameError::Empty { width, height });
        }
        if width > max_width || height > max_height {
            return Err(FrameError::TooLarge { width, height, max_width, max_height });
        }
        if self.stride < width {
            return Err(FrameError::StrideTooSmall { stride: self.stride, width });
        }
        if self.bytes() != payload_len as u64 {
            return Err(FrameError::LengthMismatch { expected: self.bytes(), payload: payload_len });
        }
        Ok(())
    }
}

/// Current version, 0 × 0 (iceoryx2 writes it into a loaned frame first).
impl Default for FrameHeader {
    fn default() -> Self {
        Self::mono8(0, 0)
    }
}
