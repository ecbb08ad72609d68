//! What a client counts of what its [`crate::rig_view::RigView`] passes
//! on, and the status it publishes about itself: the line publishes
//! `LineStatus` for `upm status`; a client without such a status (the
//! operator page) keeps the defaults.

use ipc_types::LineStatus;

pub trait ClientCounters: Send + Sync + 'static {
    /// A pick was passed on to the cell.
    fn pick_sent(&self) {}
    /// A changeover was loaded (`true`) or refused.
    fn recipe_outcome(&self, _loaded: bool) {}
    /// Whether the view publishes [`Self::write_line_status`] on `upm/line`.
    fn publishes_line_status(&self) -> bool {
        false
    }
    /// The client's counters into `out` (its header is the view's).
    fn write_line_status(&self, _out: &mut LineStatus) {}
}

/// A client that counts nothing through the view and publishes no status.
#[derive(Debug, Default, Clone, Copy)]
pub struct NoCounters;

impl ClientCounters for NoCounters {}
