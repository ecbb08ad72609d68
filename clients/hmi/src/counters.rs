//! What the operator page counted: logins, refusals and what it passed
//! on. Shown at `/api/status` and printed when the server stops.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use upm_rig_client::client_counters::ClientCounters;

#[derive(Debug, Default)]
pub struct HmiCounters {
    pub logins: AtomicU64,
    /// Logins with an unknown user or a wrong password.
    pub login_failures: AtomicU64,
    /// Control requests without a valid session.
    pub unauthorized: AtomicU64,
    /// Requests whose body or path was not understood.
    pub bad_requests: AtomicU64,
    /// Start, stop and resume passed on to the core, and those the rig's
    /// view could not pass on.
    pub commands_sent: AtomicU64,
    pub commands_failed: AtomicU64,
    pub recipes_loaded: AtomicU64,
    pub recipes_refused: AtomicU64,
    /// WebSocket connections opened so far, and open now.
    pub live_connections: AtomicU64,
    pub live_open: AtomicU64,
}

impl HmiCounters {
    pub fn count(counter: &AtomicU64) {
        counter.fetch_add(1, Relaxed);
    }

    /// (name, value) of each counter, for `/api/status` and the exit line.
    pub fn all(&self) -> [(&'static str, u64); 10] {
        [
            ("logins", self.logins.load(Relaxed)),
            ("login_failures", self.login_failures.load(Relaxed)),
            ("unauthorized", self.unauthorized.load(Relaxed)),
            ("bad_requests", self.bad_requests.load(Relaxed)),
            ("commands_sent", self.commands_sent.load(Relaxed)),
            ("commands_failed", self.commands_failed.load(Relaxed)),
            ("recipes_loaded", self.recipes_loaded.load(Relaxed)),
            ("recipes_refused", self.recipes_refused.load(Relaxed)),
            ("live_connections", self.live_connections.load(Relaxed)),
            ("live_open", self.live_open.load(Relaxed)),
        ]
    }
}

impl ClientCounters for HmiCounters {
    fn recipe_outcome(&self, loaded: bool) {
        Self::count(if loaded { &self.recipes_loaded } else { &self.recipes_refused });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recipe_outcome_counts_where_it_belongs() {
        let c = HmiCounters::default();
        c.recipe_outcome(true);
        c.recipe_outcome(false);
        c.recipe_outcome(false);
        let all = c.all();
        assert!(all.contains(&("recipes_loaded", 1)) && all.contains(&("recipes_refused", 2)), "{all:?}");
    }
}
