//! The raw iceoryx2 reference's own node and event services.

use iceoryx2::prelude::*;
use ipc_types::rig_node::rig_node;

/// A node of its own on `prefix`.
pub fn node(prefix: &str) -> anyhow::Result<Node<ipc::Service>> {
    Ok(rig_node(prefix, None, SignalHandlingMode::Disabled)?)
}

/// An event service of the raw reference (`upm/inbox`'s settings are the
/// product's; these are the bench's own).
pub fn raw_event(
    n: &Node<ipc::Service>,
    name: &str,
) -> anyhow::Result<iceoryx2::service::port_factory::event::PortFactory<ipc::Service>> {
    n.service_builder(&ServiceName::new(name)?).event().open_or_create().map_err(|e| anyhow::anyhow!("{e:?}"))
}
