//! The live nodes on a prefix, from iceoryx2's node registry.

use iceoryx2::node::{NodeListFailure, NodeView};
use iceoryx2::prelude::*;

use crate::ports::config_with_prefix;

/// A live node: its process and when it started.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodePresence {
    pub name: String,
    pub pid: u32,
    /// CLOCK_MONOTONIC ns when the node was created.
    pub started_ns: u64,
}

/// Every live node on `prefix` whose name starts with `name_prefix`,
/// oldest first. Dead nodes' files are cleaned up on the way. An invalid
/// prefix has no nodes.
pub fn live_nodes(prefix: &str, name_prefix: &str) -> Result<Vec<NodePresence>, NodeListFailure> {
    let Ok(config) = config_with_prefix(prefix) else { return Ok(Vec::new()) };
    let mut found = Vec::new();
    Node::<ipc::Service>::list(&config, |state| {
        match state {
            NodeState::Alive(view) => {
                if let Some(d) = view.details().as_ref()
                    && d.name().as_str().starts_with(name_prefix)
                {
                    let pid = view.id().pid::<ipc::Service>().map_or(0, |p| p.value() as u32);
                    let started_ns = view.id().creation_time::<ipc::Service>().map_or(0, |t| {
                        t.seconds().saturating_mul(1_000_000_000).saturating_add(u64::from(t.nanoseconds()))
                    });
                    found.push(NodePresence { name: d.name().as_str().to_owned(), pid, started_ns });
                }
            }
            NodeState::Dead(view) => {
                // Best effort: a failure leaves files iceoryx2 retries later.
                let _ = view.try_remove_stale_resources();
            }
            NodeState::Inaccessible(_) | NodeState::Undefined(_) => {}
        }
        CallbackProgression::Continue
    })?;
    found.sort_by_key(|n| n.started_ns);
    Ok(found)
}
