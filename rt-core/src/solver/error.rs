//! Why a solve was refused. `Copy`, no allocation, names the offending field.

use core::fmt;

/// Errors of [`crate::Solver::solve`]. Indices are 0-based input positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveError {
    NoCenters,
    TooManyCenters {
        given: usize,
        capacity: usize,
    },
    TooManyParts {
        given: usize,
        capacity: usize,
    },
    TooManyCurls {
        given: usize,
        capacity: usize,
    },
    /// `mu_m_g` is not a finite positive number.
    InvalidMuMg,
    /// `k_max` is not in (0, 1].
    InvalidKMax,
    NonFiniteCenter {
        center: usize,
    },
    NonFinitePartPosition {
        part: usize,
    },
    NonFinitePartForce {
        part: usize,
    },
    NonFiniteCurlPosition {
        curl: usize,
    },
    NonFiniteCurl {
        curl: usize,
    },
    /// A constrained point is closer to a center than `min_center_distance`.
    PartOnCenter {
        part: usize,
        center: usize,
    },
    CurlOnCenter {
        curl: usize,
        center: usize,
    },
    /// Distances or scaled targets overflowed f64 (absurdly large inputs).
    Overflow,
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::NoCenters => write!(f, "centers: at least one rotation center is required"),
            Self::TooManyCenters { given, capacity } => {
                write!(f, "centers: {given} given, capacity is {capacity}")
            }
            Self::TooManyParts { given, capacity } => {
                write!(f, "parts: {given} given, capacity is {capacity}")
            }
            Self::TooManyCurls { given, capacity } => {
                write!(f, "curls: {given} given, capacity is {capacity}")
            }
            Self::InvalidMuMg => write!(f, "mu_m_g: must be a finite number > 0"),
            Self::InvalidKMax => write!(f, "k_max: must be a finite number in (0, 1]"),
            Self::NonFiniteCenter { center } => {
                write!(f, "centers[{center}]: coordinates must be finite numbers")
            }
            Self::NonFinitePartPosition { part } => {
                write!(f, "parts[{part}].position: must be finite numbers")
            }
            Self::NonFinitePartForce { part } => {
                write!(f, "parts[{part}].force: must be finite numbers")
            }
            Self::NonFiniteCurlPosition { curl } => {
                write!(f, "curls[{curl}].position: must be finite numbers")
            }
            Self::NonFiniteCurl { curl } => write!(f, "curls[{curl}].curl: must be a finite number"),
            Self::PartOnCenter { part, center } => {
                write!(f, "parts[{part}].position: sits on centers[{center}] (the field is singular there)")
            }
            Self::CurlOnCenter { curl, center } => {
                write!(f, "curls[{curl}].position: sits on centers[{center}] (the field is singular there)")
            }
            Self::Overflow => write!(f, "input: numbers too large, the system overflows f64"),
        }
    }
}

impl core::error::Error for SolveError {}
