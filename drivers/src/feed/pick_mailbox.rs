//! The picks an external robot reports (`PickCommand`), from the core's io
//! thread to the cell where it steps: one slot per pick pose holding the
//! part's id (0: none), written and taken wait-free.

use core::fmt;
use core::sync::atomic::{AtomicU32, AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

use ipc_types::MAX_PICK_POSES;

/// Posted picks, one per pose; a newer post for a pose replaces an older
/// one the cell has not taken yet.
#[derive(Debug, Default)]
pub struct PickMailbox {
    slots: [AtomicU32; MAX_PICK_POSES],
    /// Posts the cell refused: that part was not ready at that pose.
    refused: AtomicU64,
    taken: AtomicU64,
}

impl PickMailbox {
    /// The robot took `part_id` from pose `pose`; false if there is no
    /// such pose slot.
    pub fn post(&self, pose: u32, part_id: u32) -> bool {
        match self.slots.get(pose as usize) {
            Some(slot) => {
                slot.store(part_id, Relaxed);
                true
            }
            None => false,
        }
    }

    /// Posts the cell carried out, and refused.
    pub fn taken(&self) -> u64 {
        self.taken.load(Relaxed)
    }
    pub fn refused(&self) -> u64 {
        self.refused.load(Relaxed)
    }

    /// The part posted for `pose` (0: none), taking it.
    pub(super) fn take(&self, pose: usize) -> u32 {
        self.slots.get(pose).map_or(0, |s| s.swap(0, Relaxed))
    }

    pub(super) fn outcome(&self, carried_out: bool) {
        let counter = if carried_out { &self.taken } else { &self.refused };
        counter.fetch_add(1, Relaxed);
    }
}

/// A cell's mailbox, if one was asked for; a clone reads none.
#[derive(Default)]
pub(super) struct MailboxSlot(pub(super) Option<Arc<PickMailbox>>);

impl Clone for MailboxSlot {
    fn clone(&self) -> Self {
        Self(None)
    }
}

impl fmt::Debug for MailboxSlot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0.is_some() { "MailboxSlot(open)" } else { "MailboxSlot(none)" })
    }
}
