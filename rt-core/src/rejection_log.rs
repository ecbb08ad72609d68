//! The core's own log of refused messages (io thread only): one line per
//! rejection, at most one a second, with how many were not shown since.
//! Every rejection is also counted by reason and answered on
//! `upm/rejection`; this is for the operator reading the core's stderr.

use ipc_types::Rejection;

/// At most one line per this many ns.
const EVERY_NS: u64 = 1_000_000_000;

#[derive(Debug, Default)]
pub struct RejectionLog {
    last_ns: Option<u64>,
    not_shown: u64,
}

impl RejectionLog {
    /// Log `r` (refused at `now_ns`, its `stamp_ns`) if a line is due, else
    /// count it.
    pub fn note(&mut self, r: &Rejection, now_ns: u64) {
        if self.last_ns.is_some_and(|t| now_ns.saturating_sub(t) < EVERY_NS) {
            self.not_shown += 1;
            return;
        }
        if self.not_shown > 0 {
            eprintln!("upm-core: {r} (and {} more rejections in the last second)", self.not_shown);
        } else {
            eprintln!("upm-core: {r}");
        }
        self.last_ns = Some(now_ns);
        self.not_shown = 0;
    }
}
