//! Wrong passwords are slowed down per client: each failure from an
//! address doubles the wait before that address's next login is checked
//! (0.5 s after the first, at most [`MAX_DELAY`]); a login that works
//! clears it. Addresses quiet for [`FORGET_AFTER`] are forgotten, and the
//! table never holds more than [`MAX_CLIENTS`].

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::Mutex;
use std::time::{Duration, Instant};

const FIRST_DELAY: Duration = Duration::from_millis(500);
pub const MAX_DELAY: Duration = Duration::from_secs(30);
const FORGET_AFTER: Duration = Duration::from_secs(15 * 60);
const MAX_CLIENTS: usize = 10_000;

#[derive(Debug, Clone, Copy)]
struct Failures {
    count: u32,
    last: Instant,
}

#[derive(Debug, Default)]
pub struct LoginThrottle {
    clients: Mutex<HashMap<IpAddr, Failures>>,
}

/// The wait before a login checked after `failures` wrong ones.
pub fn delay_after(failures: u32) -> Duration {
    match failures {
        0 => Duration::ZERO,
        n => FIRST_DELAY.saturating_mul(1u32 << (n - 1).min(16)).min(MAX_DELAY),
    }
}

impl LoginThrottle {
    /// How long `client` waits before its login is checked.
    pub fn delay(&self, client: IpAddr) -> Duration {
        let clients = self.clients.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        delay_after(clients.get(&client).map_or(0, |f| f.count))
    }

    /// One more wrong password from `client`; returns its failures so far.
    pub fn failed(&self, client: IpAddr) -> u32 {
        let mut clients = self.clients.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let now = Instant::now();
        if clients.len() >= MAX_CLIENTS {
            clients.retain(|_, f| now.duration_since(f.last) < FORGET_AFTER);
        }
        if clients.len() >= MAX_CLIENTS && !clients.contains_key(&client) {
            // Full of recent failures: the oldest gives way.
            if let Some(oldest) = clients.iter().min_by_key(|(_, f)| f.last).map(|(ip, _)| *ip) {
                clients.remove(&oldest);
            }
        }
        let f = clients.entry(client).or_insert(Failures { count: 0, last: now });
        if now.duration_since(f.last) >= FORGET_AFTER {
            f.count = 0;
        }
        f.count = f.count.saturating_add(1);
        f.last = now;
        f.count
    }

    /// A login that worked: `client` starts afresh.
    pub fn succeeded(&self, client: IpAddr) {
        self.clients.lock().unwrap_or_else(std::sync::PoisonError::into_inner).remove(&client);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_failure_doubles_the_wait_up_to_the_cap_and_success_clears_it() {
        let t = LoginThrottle::default();
        let (a, b) = (IpAddr::from([10, 0, 0, 1]), IpAddr::from([10, 0, 0, 2]));
        assert_eq!(t.delay(a), Duration::ZERO);
        assert_eq!(t.failed(a), 1);
        assert_eq!(t.delay(a), Duration::from_millis(500));
        t.failed(a);
        assert_eq!(t.delay(a), Duration::from_secs(1));
        assert_eq!(t.delay(b), Duration::ZERO, "another client is not slowed");
        for _ in 0..40 {
            t.failed(a);
        }
        assert_eq!(t.delay(a), MAX_DELAY);
        t.succeeded(a);
        assert_eq!(t.delay(a), Duration::ZERO);
    }
}
