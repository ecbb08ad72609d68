//! What a live capture did, for every camera backend.

/// What a live capture did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LiveStats {
    pub published: u64,
    /// Buffers the driver marked corrupted, or shorter than a frame.
    pub bad_buffers: u64,
    /// Frames lost before they reached us (gaps in the camera's numbering).
    pub dropped: u64,
}

impl core::fmt::Display for LiveStats {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "{} frames published, {} bad buffers skipped, {} dropped before us",
            self.published, self.bad_buffers, self.dropped
        )
    }
}
