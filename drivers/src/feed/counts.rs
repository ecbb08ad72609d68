//! What a feed cell has done, and each pick as the robot saw it.

/// Counters since the cell was built.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FeedCounts {
    /// Parts that landed on the plate.
    pub arrived: u64,
    /// Parts the robot took.
    pub picked: u64,
    /// Parts that left the plate any other way.
    pub lost: u64,
    /// Arrivals that found no free spot in the infeed region at once (each
    /// waits and tries again a millisecond later).
    pub arrivals_blocked: u64,
    /// Parts on the plate now.
    pub on_plate: u32,
    /// Recipes switched to while running.
    pub changeovers: u32,
}

/// One pick, at the instant the robot closed on the part, against the
/// simulator's truth.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PickRecord {
    /// Simulated time (s).
    pub t: f64,
    pub part_id: u32,
    pub class: u32,
    /// Index of the recipe's `[[pick]]`.
    pub pose: u32,
    /// Distance from the pose (m).
    pub position_error: f64,
    /// Angle from the pose's θ, modulo the outline's symmetry (rad).
    pub angle_error: f64,
    /// From arrival to pick (s).
    pub on_plate_s: f64,
}
