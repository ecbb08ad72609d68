//! PartStates: vision → core, the pose and velocity of every part seen.

use crate::header::{HeaderError, OldStamps};
use core::fmt;

#[cfg(feature = "iceoryx2")]
use iceoryx2::prelude::ZeroCopySend;

use crate::capacity::MAX_PARTS;
use crate::part_shape::{
    MAX_SHAPE_VERTICES, SHAPE_DISC, SHAPE_POINT, SHAPE_POLYGON, ShapeError, check_disc, check_polygon,
};
use crate::reject_reason::RejectReason;
use crate::validation::{ValidationLimits, first_non_finite};

/// One part as seen by vision. Pose in plate coordinates (m, rad),
/// velocity in m/s and rad/s, and its contact outline (`shape`): a point
/// (the paper's model), a disc of `radius`, or a convex polygon of
/// `vertex_count` `vertices` in the part's own frame (m, relative to its
/// position; turned by `theta` into plate axes). Fields a shape does not
/// use are ignored.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::PartState.v6"))]
pub struct PartState {
    /// Tracking id, unique within one message.
    pub id: u32,
    /// Part class code (what the part is, e.g. for sorting).
    pub class: u32,
    /// Friction class code (which μ applies).
    pub friction_class: u32,
    /// [`SHAPE_POINT`], [`SHAPE_DISC`] or [`SHAPE_POLYGON`].
    pub shape: u32,
    pub x: f64,
    pub y: f64,
    pub theta: f64,
    pub vx: f64,
    pub vy: f64,
    pub omega: f64,
    /// A disc's radius (m).
    pub radius: f64,
    /// A polygon's number of used `vertices`.
    pub vertex_count: u32,
    /// Unused, keep 0 (keeps the layout free of padding).
    pub reserved: u32,
    /// A polygon's vertices in order, in the part's frame (m).
    pub vertices: [[f64; 2]; MAX_SHAPE_VERTICES],
}

// No implicit padding: every byte of the shared layout is a named field.
const _: () = assert!(size_of::<PartState>() == 4 * 4 + 7 * 8 + 2 * 4 + MAX_SHAPE_VERTICES * 16);

impl PartState {
    /// All zeros.
    pub const ZERO: Self = Self::new(0, 0, 0, [0.0; 3], [0.0; 3]);

    /// A point part with pose (x, y, θ) and velocity (vx, vy, ω).
    pub const fn new(id: u32, class: u32, friction_class: u32, pose: [f64; 3], velocity: [f64; 3]) -> Self {
        Self {
            id,
            class,
            friction_class,
            shape: SHAPE_POINT,
            x: pose[0],
            y: pose[1],
            theta: pose[2],
            vx: velocity[0],
            vy: velocity[1],
            omega: velocity[2],
            radius: 0.0,
            vertex_count: 0,
            reserved: 0,
            vertices: [[0.0; 2]; MAX_SHAPE_VERTICES],
        }
    }

    /// The same part as a disc of `radius` (m); checked by `validate`.
    pub const fn with_disc(mut self, radius: f64) -> Self {
        self.shape = SHAPE_DISC;
        self.radius = radius;
        self
    }

    /// The same part as a polygon with `vertices` in its own frame (m).
    /// More than [`MAX_SHAPE_VERTICES`] is refused here; the rest of the
    /// check is `validate`'s.
    pub fn with_polygon(mut self, vertices: &[[f64; 2]]) -> Result<Self, ShapeError> {
        let used = self.vertices.get_mut(..vertices.len()).ok_or(ShapeError::VertexCount)?;
        used.copy_from_slice(vertices);
        self.shape = SHAPE_POLYGON;
        self.vertex_count = vertices.len() as u32;
        Ok(self)
    }

    /// The used polygon vertices (`vertex_count` clamped to the capacity).
    pub fn polygon(&self) -> &[[f64; 2]] {
        &self.vertices[..(self.vertex_count as usize).min(MAX_SHAPE_VERTICES)]
    }

    /// Whether the outline is one of the three, well formed and no larger
    /// than `max_extent` (m) from the part's position.
    pub fn check_shape(&self, max_extent: f64) -> Result<(), ShapeError> {
        match self.shape {
            SHAPE_POINT => Ok(()),
            SHAPE_DISC => check_disc(self.radius, max_extent),
            SHAPE_POLYGON => {
                if self.vertex_count as usize > MAX_SHAPE_VERTICES {
                    return Err(ShapeError::VertexCount);
                }
                check_polygon(self.polygon(), max_extent)
            }
            _ => Err(ShapeError::Code),
        }
    }
}

/// Vision → core: every part seen in one camera frame.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend), type_name("upm::PartStates.v6"))]
pub struct PartStates {
    pub protocol_version: u32,
    /// Number of used entries of `parts`.
    pub count: u32,
    pub seq: u64,
    /// CLOCK_MONOTONIC ns of the camera frame the states come from.
    pub stamp_ns: u64,
    pub parts: [PartState; MAX_PARTS],
}

const _: () = assert!(size_of::<PartStates>() == 4 + 4 + 8 + 8 + MAX_PARTS * size_of::<PartState>());

/// Why a [`PartStates`] was rejected. Indices refer to `parts`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartStatesError {
    /// Protocol version, count or stamp.
    Header(HeaderError),

    NonFinite {
        index: usize,
        field: &'static str,
    },
    OffPlate {
        index: usize,
        field: &'static str,
    },
    UnknownClass {
        index: usize,
        class: u32,
    },
    UnknownFrictionClass {
        index: usize,
        friction_class: u32,
    },
    DuplicateId {
        index: usize,
        first_index: usize,
        id: u32,
    },
    /// The outline is malformed ([`ShapeError::field`] names the field).
    Shape {
        index: usize,
        error: ShapeError,
    },
}

impl fmt::Display for PartStatesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Header(h) => h.fmt_in("part_states", f),
            Self::NonFinite { index, field } => write!(f, "part_states.parts[{index}].{field} is not finite"),
            Self::OffPlate { index, field } => {
                write!(f, "part_states.parts[{index}].{field} is off the plate")
            }
            Self::UnknownClass { index, class } => {
                write!(f, "part_states.parts[{index}].class {class} is not a configured class")
            }
            Self::UnknownFrictionClass { index, friction_class } => write!(
                f,
                "part_states.parts[{index}].friction_class {friction_class} is not a configured friction class"
            ),
            Self::DuplicateId { index, first_index, id } => {
                write!(f, "part_states.parts[{index}].id {id} duplicates parts[{first_index}]")
            }
            Self::Shape { index, error } => {
                write!(f, "part_states.parts[{index}].{}: {error}", error.field())
            }
        }
    }
}

impl core::error::Error for PartStatesError {}

impl PartStatesError {
    /// The counter this rejection is counted under.
    pub const fn reason(&self) -> RejectReason {
        match self {
            Self::Header(h) => h.reason(),
            Self::NonFinite { .. } => RejectReason::NonFinite,
            Self::OffPlate { .. } => RejectReason::OffPlate,
            Self::UnknownClass { .. } | Self::UnknownFrictionClass { .. } => RejectReason::UnknownClass,
            Self::DuplicateId { .. } => RejectReason::DuplicateId,
            Self::Shape { .. } => RejectReason::BadShape,
        }
    }
}

crate::counted_message::counted_message!(
    PartStates,
    parts / parts_mut: [PartState; MAX_PARTS],
    new {}
);

impl PartStates {
    /// Check the whole message; the first problem found is returned.
    /// Allocation-free, O(count²) for the duplicate-id check (≤ 2016 compares).
    pub fn validate(&self, limits: &ValidationLimits) -> Result<(), PartStatesError> {
        self.check_counted_header(OldStamps::Reject, limits).map_err(PartStatesError::Header)?;
        let parts = self.parts();
        for (index, p) in parts.iter().enumerate() {
            let floats =
                [("x", p.x), ("y", p.y), ("theta", p.theta), ("vx", p.vx), ("vy", p.vy), ("omega", p.omega)];
            if let Some(field) = first_non_finite(floats) {
                return Err(PartStatesError::NonFinite { index, field });
            }
            if !limits.is_on_plate_x(p.x) {
                return Err(PartStatesError::OffPlate { index, field: "x" });
            }
            if !limits.is_on_plate_y(p.y) {
                return Err(PartStatesError::OffPlate { index, field: "y" });
            }
            if p.class >= limits.part_class_count {
                return Err(PartStatesError::UnknownClass { index, class: p.class });
            }
            if p.friction_class >= limits.friction_class_count {
                return Err(PartStatesError::UnknownFrictionClass {
                    index,
                    friction_class: p.friction_class,
                });
            }
            p.check_shape(limits.max_part_extent())
                .map_err(|error| PartStatesError::Shape { index, error })?;
            if let Some(first_index) = parts[..index].iter().position(|q| q.id == p.id) {
                return Err(PartStatesError::DuplicateId { index, first_index, id: p.id });
            }
        }
        Ok(())
    }
}
