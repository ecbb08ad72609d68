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
    /// `k_bounds` is neither empty nor one per center.
    KBoundsLength {
        given: usize,
        centers: usize,
    },
    /// `k_bounds[center]` is not in (0, 1].
    InvalidKBound {
        center: usize,
    },
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
    /// A part's shape cannot be integrated.
    PartShape {
        part: usize,
        error: super::ShapeError,
    },
    /// A curl point's shape cannot be integrated.
    CurlShape {
        curl: usize,
        error: super::ShapeError,
    },
    /// A finite input beyond [`MAX_INPUT_MAGNITUDE`] (positions in m, forces
    /// and curls relative to μmg, μmg itself), where sums could overflow.
    OutOfRange {
        field: InputField,
        index: usize,
    },
}

/// Largest magnitude the solver accepts for a coordinate (m), for μmg (N),
/// and for a requested force or curl divided by μmg. Far beyond any plate,
/// small enough that no sum of squares of the system overflows f64.
pub const MAX_INPUT_MAGNITUDE: f64 = 1e12;

/// Which input an [`SolveError::OutOfRange`] names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputField {
    MuMg,
    Center,
    PartPosition,
    PartForce,
    CurlPosition,
    Curl,
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
            Self::KBoundsLength { given, centers } => {
                write!(f, "k_bounds: {given} given, need none or one per center ({centers})")
            }
            Self::InvalidKBound { center } => {
                write!(f, "k_bounds[{center}]: must be a finite number in (0, 1]")
            }
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
            Self::PartShape { part, error } => write!(f, "parts[{part}].shape: {error}"),
            Self::CurlShape { curl, error } => write!(f, "curls[{curl}].shape: {error}"),
            Self::OutOfRange { field, index } => {
                let limit = MAX_INPUT_MAGNITUDE;
                match field {
                    InputField::MuMg => write!(f, "mu_m_g: beyond {limit:e} N"),
                    InputField::Center => write!(f, "centers[{index}]: a coordinate beyond {limit:e} m"),
                    InputField::PartPosition => {
                        write!(f, "parts[{index}].position: a coordinate beyond {limit:e} m")
                    }
                    InputField::PartForce => write!(f, "parts[{index}].force: beyond {limit:e} × mu_m_g"),
                    InputField::CurlPosition => {
                        write!(f, "curls[{index}].position: a coordinate beyond {limit:e} m")
                    }
                    InputField::Curl => write!(f, "curls[{index}].curl: beyond {limit:e} × mu_m_g per m"),
                }
            }
        }
    }
}

impl core::error::Error for SolveError {}
