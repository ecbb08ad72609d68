//! What a logical command (LRD, LWR, LRW) may do to a SubDevice's process image.

/// What a logical command may do: read into the frame, write from it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogicalKind {
    pub read: bool,
    pub write: bool,
}
