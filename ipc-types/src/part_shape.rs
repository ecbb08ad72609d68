//! A part's contact outline as the wire carries it (in [`crate::PartState`])
//! and the one check every reader shares: a point, a disc, or a convex
//! polygon of at most [`MAX_SHAPE_VERTICES`] vertices.

use core::fmt;

/// Most vertices of a polygon outline.
pub const MAX_SHAPE_VERTICES: usize = 8;
/// The smallest outline (m): a disc's radius, a polygon's √area. Smaller
/// ones are numerically a point and would overflow the solver's rows.
pub const MIN_OUTLINE_M: f64 = 1e-4;
/// The farthest an outline may reach (m) from its part's position, on
/// any plate: it keeps every product of two coordinates finite however
/// the outline is turned (an unbounded plate would let 1e308 through).
pub const MAX_OUTLINE_M: f64 = 1e3;
/// The smallest turn (rad) at a polygon's vertex: nearly straight corners
/// could turn the other way once the outline is rotated into plate axes.
const MIN_TURN: f64 = 1e-9;

/// `PartState::shape`: the paper's point part (the field at its position).
pub const SHAPE_POINT: u32 = 0;
/// `PartState::shape`: a disc of `radius`.
pub const SHAPE_DISC: u32 = 1;
/// `PartState::shape`: a convex polygon of `vertex_count` `vertices`.
pub const SHAPE_POLYGON: u32 = 2;

/// Why an outline is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShapeError {
    /// The shape code is none of [`SHAPE_POINT`], [`SHAPE_DISC`], [`SHAPE_POLYGON`].
    Code,
    /// A disc's radius is not a finite number ≥ [`MIN_OUTLINE_M`].
    Radius,
    /// Fewer than 3 or more than [`MAX_SHAPE_VERTICES`] vertices.
    VertexCount,
    /// A vertex is not finite.
    NonFinite,
    /// The polygon turns both ways (or not at all at a vertex), crosses
    /// itself or has no area.
    NotConvex,
    /// The polygon's area is below [`MIN_OUTLINE_M`]².
    TooSmall,
    /// A disc's radius is larger than the plate's larger half-extent (or
    /// [`MAX_OUTLINE_M`]).
    RadiusTooLarge,
    /// A vertex lies farther from the part's position than the plate's
    /// larger half-extent (or [`MAX_OUTLINE_M`]).
    VertexTooFar,
}

impl fmt::Display for ShapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Code => {
                write!(f, "must be {SHAPE_POINT} (point), {SHAPE_DISC} (disc) or {SHAPE_POLYGON} (polygon)")
            }
            Self::Radius => write!(f, "radius must be a finite number ≥ {MIN_OUTLINE_M} m"),
            Self::VertexCount => write!(f, "a polygon needs 3 to {MAX_SHAPE_VERTICES} vertices"),
            Self::NonFinite => write!(f, "vertices must be finite numbers"),
            Self::NotConvex => write!(f, "the polygon must be convex, simple and of non-zero area"),
            Self::TooSmall => write!(f, "the polygon's area must be at least ({MIN_OUTLINE_M} m)²"),
            Self::RadiusTooLarge => write!(f, "the disc is larger than the plate (or {MAX_OUTLINE_M} m)"),
            Self::VertexTooFar => {
                write!(f, "a vertex lies farther out than the plate reaches (or {MAX_OUTLINE_M} m)")
            }
        }
    }
}

impl core::error::Error for ShapeError {}

impl ShapeError {
    /// The `PartState` field the error is about.
    pub const fn field(&self) -> &'static str {
        match self {
            Self::Code => "shape",
            Self::Radius | Self::RadiusTooLarge => "radius",
            Self::VertexCount => "vertex_count",
            Self::NonFinite | Self::NotConvex | Self::TooSmall | Self::VertexTooFar => "vertices",
        }
    }
}

/// A disc's radius: finite, ≥ [`MIN_OUTLINE_M`] and at most `max_extent`
/// and [`MAX_OUTLINE_M`] (m).
pub fn check_disc(radius: f64, max_extent: f64) -> Result<(), ShapeError> {
    if !(radius.is_finite() && radius >= MIN_OUTLINE_M) {
        return Err(ShapeError::Radius);
    }
    if radius > max_extent.min(MAX_OUTLINE_M) || max_extent.is_nan() {
        return Err(ShapeError::RadiusTooLarge);
    }
    Ok(())
}

/// A polygon: 3 to [`MAX_SHAPE_VERTICES`] finite vertices, in order (either
/// winding), convex (every vertex turning by more than 1e-9 rad), simple,
/// of area ≥ [`MIN_OUTLINE_M`]², none farther than `max_extent` or
/// [`MAX_OUTLINE_M`] (m) from the origin. Allocation-free.
pub fn check_polygon(v: &[[f64; 2]], max_extent: f64) -> Result<(), ShapeError> {
    let n = v.len();
    if !(3..=MAX_SHAPE_VERTICES).contains(&n) {
        return Err(ShapeError::VertexCount);
    }
    if v.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return Err(ShapeError::NonFinite);
    }
    let reach = max_extent.min(MAX_OUTLINE_M);
    if max_extent.is_nan() || v.iter().any(|p| p[0].hypot(p[1]) > reach) {
        return Err(ShapeError::VertexTooFar);
    }
    // Every turn the same way and the turns adding to one full circle:
    // convex and simple (a star turns one way too, but twice round).
    let (mut sign, mut turned, mut area2) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..n {
        let (a, b, c) = (v[i], v[(i + 1) % n], v[(i + 2) % n]);
        let e1 = [b[0] - a[0], b[1] - a[1]];
        let e2 = [c[0] - b[0], c[1] - b[1]];
        let cross = e1[0] * e2[1] - e1[1] * e2[0];
        let scale = e1[0].hypot(e1[1]) * e2[0].hypot(e2[1]);
        // False for NaN too (an overflowed cross product).
        let turns = cross.abs() > MIN_TURN * scale;
        if !turns || (sign != 0.0 && cross.signum() != sign) {
            return Err(ShapeError::NotConvex);
        }
        sign = cross.signum();
        turned += cross.atan2(e1[0] * e2[0] + e1[1] * e2[1]);
        area2 += a[0] * b[1] - b[0] * a[1];
    }
    if (turned.abs() - core::f64::consts::TAU).abs() > 1e-6 || !area2.is_finite() {
        return Err(ShapeError::NotConvex);
    }
    if 0.5 * area2.abs() < MIN_OUTLINE_M * MIN_OUTLINE_M {
        return Err(ShapeError::TooSmall);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn convex_polygons_pass_and_others_name_their_fault() {
        let square = [[0.01, 0.01], [-0.01, 0.01], [-0.01, -0.01], [0.01, -0.01]];
        assert_eq!(check_polygon(&square, 1.0), Ok(()));
        let mut cw = square;
        cw.reverse();
        assert_eq!(check_polygon(&cw, 1.0), Ok(()));
        let bowtie = [[0.01, 0.01], [-0.01, -0.01], [-0.01, 0.01], [0.01, -0.01]];
        assert_eq!(check_polygon(&bowtie, 1.0), Err(ShapeError::NotConvex));
        let line = [[0.0, 0.0], [0.01, 0.0], [0.02, 0.0]];
        assert_eq!(check_polygon(&line, 1.0), Err(ShapeError::NotConvex));
        let star: Vec<[f64; 2]> = (0..5)
            .map(|k| {
                let a = core::f64::consts::TAU * (2 * k) as f64 / 5.0;
                [a.cos(), a.sin()]
            })
            .collect();
        assert_eq!(check_polygon(&star, 2.0), Err(ShapeError::NotConvex));
        assert_eq!(check_polygon(&square[..2], 1.0), Err(ShapeError::VertexCount));
        assert_eq!(
            check_polygon(&[[f64::NAN, 0.0], [1.0, 0.0], [0.0, 1.0]], 2.0),
            Err(ShapeError::NonFinite)
        );
        assert_eq!(check_polygon(&square, 0.01), Err(ShapeError::VertexTooFar));
        assert_eq!(check_polygon(&square, f64::NAN), Err(ShapeError::VertexTooFar));
        assert_eq!(check_disc(0.01, 1.0), Ok(()));
        assert_eq!(check_disc(0.0, 1.0), Err(ShapeError::Radius));
        assert_eq!(check_disc(0.99 * MIN_OUTLINE_M, 1.0), Err(ShapeError::Radius));
        let tiny = square.map(|v| [v[0] * 1e-3, v[1] * 1e-3]);
        assert_eq!(check_polygon(&tiny, 1.0), Err(ShapeError::TooSmall));
        // A corner that barely turns is refused: turned into plate axes it
        // could round the other way.
        let up = f64::from_bits((-0.01f64).to_bits() - 1);
        let flat = [[-0.01, -0.01], [0.01, -0.01], [0.02, up], [0.01, 0.01], [-0.01, 0.01]];
        assert_eq!(check_polygon(&flat, 1.0), Err(ShapeError::NotConvex));
        assert_eq!(check_disc(f64::INFINITY, 1.0), Err(ShapeError::Radius));
        assert_eq!(check_disc(2.0, 1.0), Err(ShapeError::RadiusTooLarge));
        assert_eq!(check_disc(0.5, f64::NAN), Err(ShapeError::RadiusTooLarge));
        // Found by the fuzz test: on an unbounded plate, a triangle out at
        // 1e308 passed and overflowed once turned.
        let huge = [[f64::MAX, 0.0], [f64::MAX, -0.26], [0.0, 0.0], [0.0, 0.17]];
        assert_eq!(check_polygon(&huge, f64::INFINITY), Err(ShapeError::VertexTooFar));
        assert_eq!(check_disc(2.0 * MAX_OUTLINE_M, f64::INFINITY), Err(ShapeError::RadiusTooLarge));
        assert_eq!(check_disc(MAX_OUTLINE_M, f64::INFINITY), Ok(()));
    }
}
