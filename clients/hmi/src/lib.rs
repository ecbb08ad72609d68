//! UPM's operator page (`upm hmi`): one page that shows the live plate,
//! its counters and health, and gives a logged-in operator start, stop,
//! resume and recipe changeovers. An axum server ([`routes`]) on a small
//! tokio runtime, the rig read by `upm_rig_client`'s view, the page's
//! state pushed over a WebSocket ([`live_message`]). See README.md and
//! docs/hmi.md.

pub mod args;
pub mod assets;
pub mod counters;
pub mod live_message;
pub mod login_throttle;
pub mod routes;
pub mod sessions;
pub mod trails;
