//! A part class's outline in its own frame, as the wire will carry it.

use ipc_types::part_shape::{ShapeError, check_disc, check_polygon};
use serde::{Deserialize, Serialize};

/// `outline = { disc = { radius = 0.015 } }` or
/// `outline = { polygon = [[x, y], …] }` (m, convex, either winding).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Outline {
    Disc { radius: f64 },
    Polygon(Vec<[f64; 2]>),
}

impl Outline {
    /// The protocol's check, for a plate whose larger half-extent is
    /// `max_extent`.
    pub fn check(&self, max_extent: f64) -> Result<(), ShapeError> {
        match self {
            Self::Disc { radius } => check_disc(*radius, max_extent),
            Self::Polygon(v) => check_polygon(v, max_extent),
        }
    }

    /// The farthest the outline reaches from the part's position (m).
    pub fn reach(&self) -> f64 {
        match self {
            Self::Disc { radius } => *radius,
            Self::Polygon(v) => v.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max),
        }
    }
}
