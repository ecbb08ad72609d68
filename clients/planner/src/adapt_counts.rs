//! What online friction learning did with its windows, as every planner reports it.

/// Counts of what the estimator did with its windows.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AdaptCounts {
    pub updates: u64,
    /// Windows with too little push to tell the scale.
    pub skipped: u64,
    /// Windows that looked like a collision or a fence, or jumped.
    pub rejected: u64,
}
