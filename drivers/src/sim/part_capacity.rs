//! How much one part holds at most: polygon vertices and contact points.

/// Most vertices of a polygon part.
pub const MAX_POLYGON_VERTICES: usize = 8;
/// Most contact points of one part (a polygon uses 2 per vertex).
pub const MAX_CONTACTS: usize = 2 * MAX_POLYGON_VERTICES;
