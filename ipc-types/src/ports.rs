//! One place that opens the rig's services, so every process asks for the
//! same fixed capacities (iceoryx2 refuses to open a service whose settings
//! differ from the creator's).

use core::fmt;

use iceoryx2::node::NodeView;
use iceoryx2::port::publisher::{Publisher, PublisherCreateError};
use iceoryx2::port::subscriber::{Subscriber, SubscriberCreateError};
use iceoryx2::prelude::*;
use iceoryx2::service::builder::publish_subscribe::PublishSubscribeOpenOrCreateError;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory;

/// Publishers per service: a restarted client may overlap its predecessor.
pub const MAX_PUBLISHERS: usize = 4;
pub const MAX_SUBSCRIBERS: usize = 16;
/// Samples a slow subscriber keeps; older ones are overwritten (the newest
/// state is what matters).
pub const SUBSCRIBER_BUFFER: usize = 8;
/// A late subscriber receives the newest sample (`upm status`).
pub const HISTORY: usize = 1;
pub const MAX_NODES: usize = 32;

/// Why a service could not be opened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpenServiceError {
    InvalidName,
    OpenOrCreate(PublishSubscribeOpenOrCreateError),
    /// The service exists, created with other settings or another payload
    /// (by a client that did not use these settings): what it has, and who
    /// is on it.
    Mismatch {
        error: PublishSubscribeOpenOrCreateError,
        found: FoundService,
    },
}

/// An existing service's settings and the processes attached to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FoundService {
    /// The payload's type name (cut to 32 bytes) and size. Small fields:
    /// this travels in an error, by value.
    pub payload_name: [u8; 32],
    pub payload_size: u32,
    pub max_publishers: u32,
    pub max_subscribers: u32,
    pub subscriber_buffer: u32,
    pub history: u32,
    pub max_nodes: u32,
    pub safe_overflow: bool,
    /// Up to three pids of live nodes on the service (its creator among them).
    pub pid_count: u8,
    pub pids: [u32; 3],
}

impl fmt::Display for OpenServiceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidName => f.write_str("invalid iceoryx2 service name"),
            Self::OpenOrCreate(e) => write!(f, "opening iceoryx2 service: {e:?}"),
            Self::Mismatch { error, found: s } => {
                write!(
                    f,
                    "opening iceoryx2 service: {error:?}; it exists with payload {} ({} bytes), \
                     max_publishers {}, max_subscribers {}, subscriber buffer {}, history {}, safe overflow {}, \
                     max_nodes {}, where UPM needs {MAX_PUBLISHERS}, {MAX_SUBSCRIBERS}, {SUBSCRIBER_BUFFER}, \
                     {HISTORY}, true, {MAX_NODES} (docs/protocol.md); ",
                    crate::detail_str(&s.payload_name),
                    s.payload_size,
                    s.max_publishers,
                    s.max_subscribers,
                    s.subscriber_buffer,
                    s.history,
                    s.safe_overflow,
                    s.max_nodes
                )?;
                match &s.pids[..usize::from(s.pid_count).min(3)] {
                    [] => f.write_str("no live process holds it (a stale service: remove the rig's files)"),
                    pids => {
                        f.write_str("created by a client still running: pid")?;
                        for (i, p) in pids.iter().enumerate() {
                            write!(f, "{}{p}", if i == 0 { " " } else { ", " })?;
                        }
                        Ok(())
                    }
                }
            }
        }
    }
}

/// True when iceoryx2 refused the open because the existing service does
/// not fit what was asked (payload, settings, overflow): then what it has is
/// worth showing.
fn is_mismatch(error: &PublishSubscribeOpenOrCreateError) -> bool {
    use iceoryx2::service::builder::publish_subscribe::PublishSubscribeOpenError as E;
    matches!(
        error,
        PublishSubscribeOpenOrCreateError::PublishSubscribeOpenError(
            E::IncompatibleTypes
                | E::IncompatibleAttributes
                | E::IncompatibleOverflowBehavior
                | E::DoesNotSupportRequestedMinBufferSize
                | E::DoesNotSupportRequestedMinHistorySize
                | E::DoesNotSupportRequestedMinSubscriberBorrowedSamples
                | E::DoesNotSupportRequestedAmountOfPublishers
                | E::DoesNotSupportRequestedAmountOfSubscribers
                | E::DoesNotSupportRequestedAmountOfNodes
        )
    )
}

/// A count from iceoryx2 as u32 (saturating: only shown).
fn small(v: usize) -> u32 {
    u32::try_from(v).unwrap_or(u32::MAX)
}

/// What the existing service `name` was created with (None if it cannot be
/// read). Start-up only: it walks iceoryx2's files.
fn found_service(node: &Node<ipc::Service>, name: &ServiceName) -> Option<FoundService> {
    let details =
        ipc::Service::details(name, node.config(), MessagingPattern::PublishSubscribe).ok().flatten()?;
    let ps = details.static_details.publish_subscribe();
    let payload = ps.message_type_details().payload;
    let mut payload_name = [0u8; 32];
    let mut text = crate::DetailText::new();
    let _ = fmt::write(&mut text, format_args!("{}", payload.type_name()));
    let n = text.len.min(payload_name.len());
    payload_name[..n].copy_from_slice(&text.bytes[..n]);
    let mut found = FoundService {
        payload_name,
        payload_size: small(payload.size()),
        max_publishers: small(ps.max_publishers()),
        max_subscribers: small(ps.max_subscribers()),
        subscriber_buffer: small(ps.subscriber_max_buffer_size()),
        history: small(ps.history_size()),
        max_nodes: small(ps.max_nodes()),
        safe_overflow: ps.has_safe_overflow(),
        pid_count: 0,
        pids: [0; 3],
    };
    let own = std::process::id();
    for state in details.dynamic_details.iter().flat_map(|d| d.nodes.iter()) {
        if let NodeState::Alive(view) = state
            && let Ok(pid) = view.id().pid::<ipc::Service>()
            && pid.value() as u32 != own
            && usize::from(found.pid_count) < found.pids.len()
        {
            found.pids[usize::from(found.pid_count)] = pid.value() as u32;
            found.pid_count += 1;
        }
    }
    Some(found)
}

impl core::error::Error for OpenServiceError {}

/// Open (or create) the publish-subscribe service `name` for payload `T`.
pub fn open_pub_sub<T: core::fmt::Debug + ZeroCopySend>(
    node: &Node<ipc::Service>,
    name: &str,
) -> Result<PortFactory<ipc::Service, T, ()>, OpenServiceError> {
    let name = ServiceName::new(name).map_err(|_| OpenServiceError::InvalidName)?;
    node.service_builder(&name)
        .publish_subscribe::<T>()
        .max_publishers(MAX_PUBLISHERS)
        .max_subscribers(MAX_SUBSCRIBERS)
        .subscriber_max_buffer_size(SUBSCRIBER_BUFFER)
        .history_size(HISTORY)
        .enable_safe_overflow(true)
        .max_nodes(MAX_NODES)
        .open_or_create()
        .map_err(|error| match is_mismatch(&error).then(|| found_service(node, &name)).flatten() {
            Some(found) => OpenServiceError::Mismatch { error, found },
            None => OpenServiceError::OpenOrCreate(error),
        })
}

/// A subscriber of payload `T` on `name`.
pub type Sub<T> = Subscriber<ipc::Service, T, ()>;
/// A publisher of payload `T`.
pub type Pub<T> = Publisher<ipc::Service, T, ()>;

/// Why a publisher or subscriber could not be created; names the service.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PortError {
    Service { service: &'static str, error: OpenServiceError },
    Publisher { service: &'static str, error: PublisherCreateError },
    Subscriber { service: &'static str, error: SubscriberCreateError },
}

impl fmt::Display for PortError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Service { service, error } => write!(f, "service {service}: {error}"),
            Self::Publisher { service, error } => {
                write!(f, "service {service}: creating a publisher: {error:?}")
            }
            Self::Subscriber { service, error } => {
                write!(f, "service {service}: creating a subscriber: {error:?}")
            }
        }
    }
}

impl core::error::Error for PortError {}

/// A publisher of `T` on `service`, opened with the rig's settings.
pub fn publisher<T: core::fmt::Debug + ZeroCopySend>(
    node: &Node<ipc::Service>,
    service: &'static str,
) -> Result<Pub<T>, PortError> {
    open_pub_sub::<T>(node, service)
        .map_err(|error| PortError::Service { service, error })?
        .publisher_builder()
        .create()
        .map_err(|error| PortError::Publisher { service, error })
}

/// A subscriber of `T` on `service`, opened with the rig's settings.
pub fn subscriber<T: core::fmt::Debug + ZeroCopySend>(
    node: &Node<ipc::Service>,
    service: &'static str,
) -> Result<Sub<T>, PortError> {
    open_pub_sub::<T>(node, service)
        .map_err(|error| PortError::Service { service, error })?
        .subscriber_builder()
        .create()
        .map_err(|error| PortError::Subscriber { service, error })
}

/// iceoryx2 config isolated to one rig (or test) by its prefix.
pub fn config_with_prefix(prefix: &str) -> Result<Config, OpenServiceError> {
    let mut config = Config::default();
    config.global.prefix = FileName::new(prefix.as_bytes()).map_err(|_| OpenServiceError::InvalidName)?;
    Ok(config)
}

/// Subscribers of camera frames (vision, a recorder, a viewer, …).
pub const FRAME_SUBSCRIBERS: usize = 4;
/// Frames a slow subscriber keeps: the newest two (each may be megabytes).
pub const FRAME_BUFFER: usize = 2;

/// A publisher of camera frames: [`crate::FrameHeader`] and the pixels.
pub type FramePub = Publisher<ipc::Service, [u8], crate::FrameHeader>;
/// A subscriber of camera frames.
pub type FrameSub = Subscriber<ipc::Service, [u8], crate::FrameHeader>;

fn open_frames(
    node: &Node<ipc::Service>,
) -> Result<PortFactory<ipc::Service, [u8], crate::FrameHeader>, PortError> {
    let service = crate::service_names::CAMERA_FRAME;
    let name = ServiceName::new(service)
        .map_err(|_| PortError::Service { service, error: OpenServiceError::InvalidName })?;
    node.service_builder(&name)
        .publish_subscribe::<[u8]>()
        .user_header::<crate::FrameHeader>()
        .max_publishers(MAX_PUBLISHERS)
        .max_subscribers(FRAME_SUBSCRIBERS)
        .subscriber_max_buffer_size(FRAME_BUFFER)
        .history_size(0)
        .enable_safe_overflow(true)
        .max_nodes(MAX_NODES)
        .open_or_create()
        .map_err(|error| PortError::Service { service, error: OpenServiceError::OpenOrCreate(error) })
}

/// A publisher of frames up to `max_bytes` of pixels each (the memory is
/// set aside at creation; a larger loan fails).
pub fn frame_publisher(node: &Node<ipc::Service>, max_bytes: usize) -> Result<FramePub, PortError> {
    let service = crate::service_names::CAMERA_FRAME;
    open_frames(node)?
        .publisher_builder()
        .initial_max_slice_len(max_bytes)
        .create()
        .map_err(|error| PortError::Publisher { service, error })
}

/// A subscriber of camera frames.
pub fn frame_subscriber(node: &Node<ipc::Service>) -> Result<FrameSub, PortError> {
    let service = crate::service_names::CAMERA_FRAME;
    open_frames(node)?.subscriber_builder().create().map_err(|error| PortError::Subscriber { service, error })
}
