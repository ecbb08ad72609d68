//! What vision publishes, whatever its source: the tracked parts as
//! `PartStates`, then a wake-up of the core's inbox and of the planners
//! (`upm/part_states` event); and the node it waits on, which says when the
//! core goes or comes back.

use std::time::Duration;

use iceoryx2::node::NodeWaitFailure;
use iceoryx2::prelude::*;
use ipc_types::discovery::CoreWatch;
use ipc_types::ports::Pub;
use ipc_types::rig_node::rig_node;
use ipc_types::wake_event::{WakeEvent, WakeNotifier};
use ipc_types::{PartState, PartStates, service_names};

use crate::Track;

/// Turn a frame's tracks into the PartStates message, each part with its
/// track's outline.
pub fn part_states(tracks: &[Track], seq: u64, stamp_ns: u64, out: &mut PartStates) {
    out.clear();
    out.seq = seq;
    out.stamp_ns = stamp_ns;
    for t in tracks.iter().filter(|t| t.missed == 0) {
        // More tracks than capacity: the rest are not reported this frame.
        let _ = out.push(t.outline.put_on(PartState::new(t.id, t.class, 0, t.pose, t.velocity)));
    }
}

#[derive(Debug)]
pub struct Outputs {
    node: Node<ipc::Service>,
    publisher: Pub<PartStates>,
    wake: WakeNotifier,
    /// Planners sleep on it.
    planners: WakeNotifier,
    core: CoreWatch,
    /// The last message published (its stamp is the previous frame's).
    last: PartStates,
}

impl Outputs {
    pub fn open(prefix: &str) -> anyhow::Result<Self> {
        let node = rig_node(
            prefix,
            Some(ipc_types::discovery::VISION_NODE),
            SignalHandlingMode::HandleTerminationRequests,
        )?;
        let publisher = ipc_types::ports::publisher::<PartStates>(&node, service_names::PART_STATES)?;
        let wake = WakeNotifier::new(&node, WakeEvent::Inbox)?;
        let planners = WakeNotifier::new(&node, WakeEvent::PartStates)?;
        let core = CoreWatch::new(prefix, Duration::from_secs(1));
        Ok(Self { node, publisher, wake, planners, core, last: PartStates::new() })
    }

    pub fn node(&self) -> &Node<ipc::Service> {
        &self.node
    }

    /// Seconds since the last published frame (0 for the first).
    pub fn dt(&self, stamp_ns: u64) -> f64 {
        if self.last.stamp_ns == 0 { 0.0 } else { stamp_ns.saturating_sub(self.last.stamp_ns) as f64 / 1e9 }
    }

    /// Publish the tracks of the frame stamped `stamp_ns` as number `seq`.
    pub fn publish(&mut self, tracks: &[Track], seq: u64, stamp_ns: u64) -> anyhow::Result<()> {
        part_states(tracks, seq, stamp_ns, &mut self.last);
        self.publisher.send_copy(self.last).map_err(|e| anyhow::anyhow!("publishing part states: {e:?}"))?;
        self.wake.notify();
        self.planners.notify();
        Ok(())
    }

    /// Say when the core goes or comes back, then wait up to `timeout` for
    /// an event; `false` once SIGINT or SIGTERM arrived.
    pub fn wait(&mut self, timeout: Duration) -> bool {
        if let Some(news) = self.core.poll() {
            eprintln!("upm-vision: {news}");
        }
        match self.node.wait(timeout) {
            Ok(()) => true,
            Err(NodeWaitFailure::Interrupt | NodeWaitFailure::TerminationRequest) => false,
        }
    }
}
