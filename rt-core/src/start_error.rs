//! Why the core could not start. Start-up only; nothing here is on a hot path.

use core::fmt;

use iceoryx2::node::NodeListFailure;
use ipc_types::ports::PortError;
use ipc_types::rig_node::RigNodeError;

use super::params::CoreParamsError;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StartError {
    Params(CoreParamsError),
    /// The service prefix is not a valid file name.
    Prefix,
    Node(RigNodeError),
    /// The clients' wake-up event could not be opened.
    WakeEvent(ipc_types::wake_event::WakeEventError),
    /// The prefix's node list could not be read (to find a running core).
    NodeList(NodeListFailure),
    /// A service could not be opened or a port created on it.
    Port(PortError),
    /// Another live upm-core owns this prefix.
    AlreadyRunning,
    /// The rig's description could not be published.
    RigInfo,
    Thread {
        thread: &'static str,
    },
    /// A thread died during start-up.
    ThreadStartup {
        thread: &'static str,
    },
}

impl fmt::Display for StartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Params(e) => write!(f, "config: {e}"),
            Self::Prefix => f.write_str("service.prefix is not a valid file name"),
            Self::Node(e) => write!(f, "{e}{}", permission_hint(e.is_permission())),
            Self::WakeEvent(e) => write!(f, "{e}"),
            Self::NodeList(e) => write!(
                f,
                "reading the iceoryx2 node list: {e:?}{}",
                permission_hint(*e == NodeListFailure::InsufficientPermissions)
            ),
            Self::Port(e) => write!(f, "{e}"),
            Self::AlreadyRunning => f.write_str(
                "another upm-core is already running on this service prefix (stop it, or use another service.prefix)",
            ),
            Self::RigInfo => f.write_str("cannot publish the rig's description on upm/rig_info"),
            Self::Thread { thread } => write!(f, "cannot spawn the {thread} thread"),
            Self::ThreadStartup { thread } => write!(f, "the {thread} thread failed during start-up"),
        }
    }
}

impl core::error::Error for StartError {}

/// The usual cause: iceoryx2's directory belongs to another user (a core
/// once run as root leaves /tmp/iceoryx2 root-owned).
fn permission_hint(permission: bool) -> &'static str {
    if permission {
        " (does /tmp/iceoryx2 or a /dev/shm file of this prefix belong to another user? see docs/deploy.md)"
    } else {
        ""
    }
}
