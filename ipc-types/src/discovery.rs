//! Who is on a rig, and which rigs run on this machine, read from
//! iceoryx2's own node registry (no extra service):
//!
//! - a process announces its role by its node's name on the rig's prefix
//!   ([`VISION_NODE`], [`PLANNER_NODE`], …); its pid and start time come
//!   with the node;
//! - a core announces its rig with a node named after the rig's prefix on
//!   the machine-wide [`DISCOVERY_PREFIX`], so `upm status` finds rigs
//!   without being told their prefix.
//!
//! Listing walks iceoryx2's files: for start-up and tools, not RT threads.

use iceoryx2::node::NodeListFailure;
use iceoryx2::prelude::*;

pub use crate::node_list::{NodePresence, live_nodes};
use crate::rig_node::{RigNodeError, rig_node};

/// Prefix on which running cores announce their rigs.
pub const DISCOVERY_PREFIX: &str = "upmdiscovery_";
/// Node name of a rig's core (one per prefix).
pub const CORE_NODE: &str = "upm-core";
/// Node names clients announce themselves with (a name that starts with
/// one of these counts).
pub const VISION_NODE: &str = "upm-vision";
pub const PLANNER_NODE: &str = "upm-planner";

/// Announce the rig on `prefix` machine-wide; keep the node as long as the
/// rig runs.
pub fn announce_rig(prefix: &str) -> Result<Node<ipc::Service>, RigNodeError> {
    rig_node(DISCOVERY_PREFIX, Some(prefix), SignalHandlingMode::Disabled)
}

/// Rigs announced by live cores: the node name is the rig's prefix.
pub fn running_rigs() -> Result<Vec<NodePresence>, NodeListFailure> {
    live_nodes(DISCOVERY_PREFIX, "")
}

/// True if a live core owns `prefix` (its node is named exactly
/// [`CORE_NODE`]; dead cores' files are cleaned up on the way). An invalid
/// prefix has no core.
pub fn core_running(prefix: &str) -> Result<bool, NodeListFailure> {
    Ok(live_nodes(prefix, CORE_NODE)?.iter().any(|n| n.name == CORE_NODE))
}

/// A client's view of whether the core on its prefix is up: a core killed
/// with SIGKILL leaves its ports behind, so a client cannot tell from its
/// ports alone. Polled from a client's loop; reads the node list at most
/// once per `every` (it walks iceoryx2's files, so not per frame).
#[derive(Debug)]
pub struct CoreWatch {
    prefix: String,
    every: std::time::Duration,
    next_check: std::time::Instant,
    alive: Option<bool>,
}

impl CoreWatch {
    pub fn new(prefix: &str, every: std::time::Duration) -> Self {
        Self { prefix: prefix.to_owned(), every, next_check: std::time::Instant::now(), alive: None }
    }

    /// Look again if a check is due. Returns the news when the core's
    /// presence changed (and at the first check), else `None`. A failing
    /// node list reads as "no core".
    pub fn poll(&mut self) -> Option<CoreNews<'_>> {
        let now = std::time::Instant::now();
        if now < self.next_check {
            return None;
        }
        self.next_check = now + self.every;
        let alive = core_running(&self.prefix).unwrap_or(false);
        (self.alive.replace(alive) != Some(alive)).then_some(CoreNews { alive, prefix: &self.prefix })
    }
}

/// A change [`CoreWatch::poll`] saw; shown as one line for a client's stderr.
#[derive(Debug, Clone, Copy)]
pub struct CoreNews<'a> {
    pub alive: bool,
    pub prefix: &'a str,
}

impl core::fmt::Display for CoreNews<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.alive {
            write!(f, "upm-core is up on prefix {:?}", self.prefix)
        } else {
            write!(f, "no upm-core on prefix {:?}; waiting for one", self.prefix)
        }
    }
}
