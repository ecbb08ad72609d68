//! One place that opens the rig's services, so every process asks for the
//! same fixed capacities (iceoryx2 refuses to open a service whose settings
//! differ from the creator's).

use core::fmt;

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
}

impl fmt::Display for OpenServiceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidName => f.write_str("invalid iceoryx2 service name"),
            Self::OpenOrCreate(e) => write!(f, "opening iceoryx2 service: {e:?}"),
        }
    }
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
        .map_err(OpenServiceError::OpenOrCreate)
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
