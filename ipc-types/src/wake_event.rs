//! Wake-up events: a publisher notifies right after it sends, so the
//! process that waits for the data wakes at once instead of at its next
//! poll. A publisher that does not notify still gets through, one poll
//! later.
//!
//! - [`WakeEvent::Inbox`] (`upm/inbox`): a client published to the core
//!   (PartStates, ForceRequest, ExplicitSchedule, CoreCommand); the core's
//!   receiver thread listens.
//! - [`WakeEvent::Frame`] (`upm/camera/frame`, the frame service's name
//!   with the event pattern): a frame source published a frame; vision
//!   listens.
//! - [`WakeEvent::PartStates`] (`upm/part_states`, the part states'
//!   service name with the event pattern): vision published PartStates;
//!   planners listen, up to [`PART_STATES_LISTENERS`] of them.
//!
//! Settings left to iceoryx2's defaults (0.10): event ids up to 255, no
//! notifier created / dropped / dead events, no deadline.

use core::fmt;

use iceoryx2::port::listener::{Listener, ListenerCreateError};
use iceoryx2::port::notifier::{Notifier, NotifierCreateError};
use iceoryx2::prelude::*;
use iceoryx2::service::builder::event::EventOpenOrCreateError;
use iceoryx2::service::port_factory::event::PortFactory;

use crate::ports::{MAX_NODES, MAX_SUBSCRIBERS};
use crate::service_names::{CAMERA_FRAME, INBOX_EVENT, PART_STATES_EVENT};

/// Which wake-up event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WakeEvent {
    Inbox,
    Frame,
    PartStates,
}

impl WakeEvent {
    /// The event service's name.
    pub const fn service(self) -> &'static str {
        match self {
            Self::Inbox => INBOX_EVENT,
            Self::Frame => CAMERA_FRAME,
            Self::PartStates => PART_STATES_EVENT,
        }
    }

    /// Listeners the event allows: for the inbox and frames, the core's
    /// receiver (or vision) and one more while a restarted one takes over;
    /// for part states, any planners and tools.
    pub const fn max_listeners(self) -> usize {
        match self {
            Self::Inbox | Self::Frame => MAX_LISTENERS,
            Self::PartStates => PART_STATES_LISTENERS,
        }
    }
}

/// Listeners of the inbox and frame events (see [`WakeEvent::max_listeners`]).
pub const MAX_LISTENERS: usize = 2;

/// Listeners of the part states event.
pub const PART_STATES_LISTENERS: usize = 16;

/// Why a wake-up event or one of its ports could not be created.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WakeEventError {
    InvalidName,
    OpenOrCreate(EventOpenOrCreateError),
    Notifier(NotifierCreateError),
    Listener(ListenerCreateError),
}

impl fmt::Display for WakeEventError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidName => f.write_str("invalid iceoryx2 event name"),
            Self::OpenOrCreate(e) => write!(f, "opening a wake-up event: {e:?}"),
            Self::Notifier(e) => write!(f, "creating a wake-up notifier: {e:?}"),
            Self::Listener(e) => write!(f, "creating a wake-up listener: {e:?}"),
        }
    }
}

impl core::error::Error for WakeEventError {}

/// Open (or create) the event, with the same settings in every process.
fn open(node: &Node<ipc::Service>, event: WakeEvent) -> Result<PortFactory<ipc::Service>, WakeEventError> {
    let name = ServiceName::new(event.service()).map_err(|_| WakeEventError::InvalidName)?;
    node.service_builder(&name)
        .event()
        .max_notifiers(MAX_SUBSCRIBERS)
        .max_listeners(event.max_listeners())
        .max_nodes(MAX_NODES)
        .open_or_create()
        .map_err(WakeEventError::OpenOrCreate)
}

/// A publisher's side: call [`WakeNotifier::notify`] after each send.
#[derive(Debug)]
pub struct WakeNotifier {
    notifier: Notifier<ipc::Service>,
    /// Failed notifications (the data still arrives, one poll later).
    pub failures: u64,
}

impl WakeNotifier {
    pub fn new(node: &Node<ipc::Service>, event: WakeEvent) -> Result<Self, WakeEventError> {
        let notifier = open(node, event)?.notifier_builder().create().map_err(WakeEventError::Notifier)?;
        Ok(Self { notifier, failures: 0 })
    }

    /// Wake the listener. Never fails the caller: a lost wake-up only costs
    /// one poll period.
    pub fn notify(&mut self) {
        if self.notifier.notify().is_err() {
            self.failures += 1;
        }
    }
}

/// The listening side (the core's receiver thread, vision, planners).
pub fn wake_listener(
    node: &Node<ipc::Service>,
    event: WakeEvent,
) -> Result<Listener<ipc::Service>, WakeEventError> {
    open(node, event)?.listener_builder().create().map_err(WakeEventError::Listener)
}
