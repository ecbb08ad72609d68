//! The core's wake-up event. A client that publishes to the core
//! (PartStates, ForceRequest, ExplicitSchedule) notifies it right after, so
//! the core's receiver thread wakes at once instead of at its next poll. A
//! client that does not notify still gets through, one poll later.

use core::fmt;

use iceoryx2::port::listener::{Listener, ListenerCreateError};
use iceoryx2::port::notifier::{Notifier, NotifierCreateError};
use iceoryx2::prelude::*;
use iceoryx2::service::builder::event::EventOpenOrCreateError;
use iceoryx2::service::port_factory::event::PortFactory;

use crate::ports::{MAX_NODES, MAX_SUBSCRIBERS};
use crate::service_names::INBOX_EVENT;

/// Why the wake-up event or one of its ports could not be created.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InboxEventError {
    InvalidName,
    OpenOrCreate(EventOpenOrCreateError),
    Notifier(NotifierCreateError),
    Listener(ListenerCreateError),
}

impl fmt::Display for InboxEventError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidName => f.write_str("invalid iceoryx2 event name"),
            Self::OpenOrCreate(e) => write!(f, "opening the core's wake-up event: {e:?}"),
            Self::Notifier(e) => write!(f, "creating a wake-up notifier: {e:?}"),
            Self::Listener(e) => write!(f, "creating the wake-up listener: {e:?}"),
        }
    }
}

impl core::error::Error for InboxEventError {}

/// Open (or create) the event, with the same settings in every process.
/// Listeners the inbox event allows: the core's receiver, and one more
/// while a restarted core takes over.
pub const MAX_LISTENERS: usize = 2;

fn open(node: &Node<ipc::Service>) -> Result<PortFactory<ipc::Service>, InboxEventError> {
    let name = ServiceName::new(INBOX_EVENT).map_err(|_| InboxEventError::InvalidName)?;
    node.service_builder(&name)
        .event()
        .max_notifiers(MAX_SUBSCRIBERS)
        .max_listeners(MAX_LISTENERS)
        .max_nodes(MAX_NODES)
        .open_or_create()
        .map_err(InboxEventError::OpenOrCreate)
}

/// A client's side: call [`InboxNotifier::notify`] after each publish.
#[derive(Debug)]
pub struct InboxNotifier {
    notifier: Notifier<ipc::Service>,
    /// Failed notifications (the message still arrives, one poll later).
    pub failures: u64,
}

impl InboxNotifier {
    pub fn new(node: &Node<ipc::Service>) -> Result<Self, InboxEventError> {
        let notifier = open(node)?.notifier_builder().create().map_err(InboxEventError::Notifier)?;
        Ok(Self { notifier, failures: 0 })
    }

    /// Wake the core's receiver. Never fails the caller: a lost wake-up only
    /// costs one receiver poll period.
    pub fn notify(&mut self) {
        if self.notifier.notify().is_err() {
            self.failures += 1;
        }
    }
}

/// The core's side, on its (non-real-time) receiver thread.
pub fn inbox_listener(node: &Node<ipc::Service>) -> Result<Listener<ipc::Service>, InboxEventError> {
    open(node)?.listener_builder().create().map_err(InboxEventError::Listener)
}
