//! Clients notice when the core on their prefix dies or comes back (a core
//! killed with SIGKILL leaves its ports behind until a live node cleans them
//! up). They say so once on stderr and keep waiting; they never crash.

use std::time::{Duration, Instant};

/// How often the node list is read (it walks /tmp/iceoryx2, so not per frame).
const CHECK_EVERY: Duration = Duration::from_secs(1);

#[derive(Debug)]
pub struct CoreWatch {
    who: &'static str,
    prefix: String,
    next_check: Instant,
    alive: Option<bool>,
}

impl CoreWatch {
    pub fn new(who: &'static str, prefix: &str) -> Self {
        Self { who, prefix: prefix.to_owned(), next_check: Instant::now(), alive: None }
    }

    /// Look again if a check is due; report a change of the core's presence.
    /// Returns whether a core was alive at the last check.
    pub fn poll(&mut self) -> bool {
        if Instant::now() >= self.next_check {
            self.next_check = Instant::now() + CHECK_EVERY;
            // A failing node list reads as "no core": the client only waits.
            let alive = rt_core::runtime::core_running(&self.prefix).unwrap_or(false);
            if self.alive != Some(alive) {
                if alive {
                    eprintln!("{}: upm-core is up on prefix {:?}", self.who, self.prefix);
                } else {
                    eprintln!("{}: no upm-core on prefix {:?}; waiting for one", self.who, self.prefix);
                }
                self.alive = Some(alive);
            }
        }
        self.alive.unwrap_or(false)
    }
}
