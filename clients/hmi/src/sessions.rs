//! Logged-in operators: a random token (the session cookie's value) per
//! login, valid for [`SESSION_LIFETIME`], kept in memory only (a restart
//! logs everyone out).

use std::collections::HashMap;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How long a login lasts.
pub const SESSION_LIFETIME: Duration = Duration::from_secs(8 * 3600);
/// The session cookie's name.
pub const COOKIE: &str = "upm_session";
/// Sessions held at most; the oldest give way.
const MAX_SESSIONS: usize = 1000;

#[derive(Debug, Clone)]
struct Session {
    user: String,
    until: Instant,
}

#[derive(Debug, Default)]
pub struct Sessions {
    by_token: Mutex<HashMap<String, Session>>,
}

impl Sessions {
    /// A new session for `user`: its token.
    pub fn open(&self, user: &str) -> anyhow::Result<String> {
        let mut bytes = [0u8; 32];
        getrandom::fill(&mut bytes).map_err(|e| anyhow::anyhow!("no randomness for a session token: {e}"))?;
        let token: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        let mut sessions = self.by_token.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let now = Instant::now();
        sessions.retain(|_, s| s.until > now);
        while sessions.len() >= MAX_SESSIONS {
            let Some(oldest) = sessions.iter().min_by_key(|(_, s)| s.until).map(|(t, _)| t.clone()) else {
                break;
            };
            sessions.remove(&oldest);
        }
        sessions.insert(token.clone(), Session { user: user.to_owned(), until: now + SESSION_LIFETIME });
        Ok(token)
    }

    /// The user of a live session `token`.
    pub fn user(&self, token: &str) -> Option<String> {
        let sessions = self.by_token.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        sessions.get(token).filter(|s| s.until > Instant::now()).map(|s| s.user.clone())
    }

    pub fn close(&self, token: &str) {
        self.by_token.lock().unwrap_or_else(std::sync::PoisonError::into_inner).remove(token);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_token_names_its_user_until_closed_and_tokens_differ() {
        let s = Sessions::default();
        let a = s.open("ann").expect("token");
        let b = s.open("ann").expect("token");
        assert_ne!(a, b);
        assert_eq!(a.len(), 64);
        assert_eq!(s.user(&a).as_deref(), Some("ann"));
        s.close(&a);
        assert_eq!(s.user(&a), None);
        assert_eq!(s.user("not-a-token"), None);
    }
}
