//! The core's iceoryx2 subscribers. They live on the receiver thread
//! (normal priority), which forwards messages to the solver through a ring:
//! `receive()` is allocation-free per message in iceoryx2 0.10, but it
//! allocates when it sets up a connection to a new publisher (a client
//! starting or restarting), which must not happen on an RT thread.
//! `ipc::Service` ports are not `Send`, so they are created on the thread
//! that uses them.

use iceoryx2::port::listener::Listener;
use iceoryx2::prelude::*;
use ipc_types::ports::Sub;
use ipc_types::rig_node::rig_node;
use ipc_types::wake_event::{WakeEvent, wake_listener};
use ipc_types::{CoreCommand, ExplicitSchedule, ForceRequest, PartStates, monotonic_now_ns, service_names};

use super::inbox::{Inbound, Inbox, InboxBuffers};
use super::start_error::StartError;

#[derive(Debug)]
pub struct IpcInbox {
    _node: Node<ipc::Service>,
    parts: Sub<PartStates>,
    requests: Sub<ForceRequest>,
    explicit: Sub<ExplicitSchedule>,
    commands: Sub<CoreCommand>,
    /// Clients notify it after publishing (see `ipc_types::wake_event`).
    wake: Listener<ipc::Service>,
    /// Receive errors (counted, never fatal).
    pub receive_errors: u64,
}

impl IpcInbox {
    /// Create the node and the three subscribers (start-up only).
    pub fn new(prefix: &str) -> Result<Self, StartError> {
        // The io thread's node handles SIGINT/SIGTERM.
        let node = rig_node(prefix, Some("upm-core-receiver"), SignalHandlingMode::Disabled)
            .map_err(StartError::Node)?;
        let parts = ipc_types::ports::subscriber::<PartStates>(&node, service_names::PART_STATES)
            .map_err(StartError::Port)?;
        let requests = ipc_types::ports::subscriber::<ForceRequest>(&node, service_names::FORCE_REQUEST)
            .map_err(StartError::Port)?;
        let explicit =
            ipc_types::ports::subscriber::<ExplicitSchedule>(&node, service_names::EXPLICIT_SCHEDULE)
                .map_err(StartError::Port)?;
        let commands = ipc_types::ports::subscriber::<CoreCommand>(&node, service_names::CORE_COMMAND)
            .map_err(StartError::Port)?;
        let wake = wake_listener(&node, WakeEvent::Inbox).map_err(StartError::WakeEvent)?;
        Ok(Self { _node: node, parts, requests, explicit, commands, wake, receive_errors: 0 })
    }

    /// Block until a client announces a message or `timeout` passes (the
    /// poll that catches clients that do not notify). Not for RT threads.
    pub fn wait(&self, timeout: core::time::Duration) {
        if self.wake.timed_wait(|_| {}, timeout).is_err() {
            // A failing listener must not turn into a busy loop.
            std::thread::sleep(core::time::Duration::from_micros(100));
        }
    }
}

/// Copy the next sample of `sub` into `dst`, stamping when it arrived.
fn take<T: Copy + core::fmt::Debug + ZeroCopySend>(
    sub: &Sub<T>,
    dst: &mut T,
    received_ns: &mut u64,
    errors: &mut u64,
) -> bool {
    match sub.receive() {
        Ok(Some(s)) => {
            *received_ns = monotonic_now_ns();
            *dst = *s.payload();
            true
        }
        Ok(None) => false,
        Err(_) => {
            *errors += 1;
            false
        }
    }
}

impl Inbox for IpcInbox {
    fn next(&mut self, buf: &mut InboxBuffers) -> Option<Inbound> {
        // Copy out of shared memory: the publisher may reuse the sample, and
        // validation must see one consistent copy.
        let (at, errors) = (&mut buf.received_ns, &mut self.receive_errors);
        if take(&self.parts, &mut *buf.parts, at, errors) {
            Some(Inbound::PartStates)
        } else if take(&self.requests, &mut *buf.request, at, errors) {
            Some(Inbound::Request)
        } else if take(&self.explicit, &mut *buf.explicit, at, errors) {
            Some(Inbound::Explicit)
        } else if take(&self.commands, &mut buf.command, at, errors) {
            Some(Inbound::Command)
        } else {
            None
        }
    }
}
