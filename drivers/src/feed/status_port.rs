//! Where a feed cell writes its status (`status.rs`): a triple buffer's
//! input, held by the cell and never by a clone of it.

use core::fmt;

use ipc_types::FeedStatus;

/// Where the cell writes its status, every `every` steps.
pub(super) struct StatusPort {
    pub(super) every: u64,
    pub(super) steps: u64,
    pub(super) out: triple_buffer::Input<FeedStatus>,
}

/// A cell's port, if one was asked for; a clone does not publish.
#[derive(Default)]
pub(super) struct StatusSlot(pub(super) Option<StatusPort>);

impl Clone for StatusSlot {
    fn clone(&self) -> Self {
        Self(None)
    }
}

impl fmt::Debug for StatusSlot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Some(p) => write!(f, "StatusSlot(every {} steps)", p.every),
            None => f.write_str("StatusSlot(none)"),
        }
    }
}
