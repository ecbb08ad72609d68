//! Why the core could not start. Start-up only; nothing here is on a hot path.

use core::fmt;

use ipc_types::ports::OpenServiceError;

use super::params::CoreParamsError;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StartError {
    Params(CoreParamsError),
    /// The service prefix is not a valid file name.
    Prefix,
    Node,
    Service {
        service: &'static str,
        error: OpenServiceError,
    },
    Port {
        service: &'static str,
    },
    /// Another live upm-core owns this prefix.
    AlreadyRunning,
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
            Self::Node => f.write_str("cannot create the iceoryx2 node"),
            Self::Service { service, error } => write!(f, "service {service}: {error}"),
            Self::Port { service } => write!(f, "cannot create a port on {service}"),
            Self::AlreadyRunning => f.write_str(
                "another upm-core is already running on this service prefix (stop it, or use another service.prefix)",
            ),
            Self::Thread { thread } => write!(f, "cannot spawn the {thread} thread"),
            Self::ThreadStartup { thread } => write!(f, "the {thread} thread failed during start-up"),
        }
    }
}

impl core::error::Error for StartError {}
