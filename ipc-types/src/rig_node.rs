//! A node on a rig's prefix whose shared memory only its user can open.
//!
//! iceoryx2 0.10 creates the per-prefix node counter segment
//! (`<prefix>…global_mgmt` in /dev/shm) world-writable so that several
//! users can share one domain. A rig's prefix belongs to one user, so every
//! UPM process tightens what it created to 0600 right after creating its node.

use core::fmt;
use std::os::unix::fs::{MetadataExt, PermissionsExt};

use iceoryx2::node::NodeCreationFailure;
use iceoryx2::prelude::*;

use crate::ports::config_with_prefix;

/// Where POSIX shared memory lives on Linux.
pub const SHM_DIR: &str = "/dev/shm";

/// Why a rig node could not be created.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RigNodeError {
    InvalidPrefix,
    InvalidName,
    Create(NodeCreationFailure),
}

impl fmt::Display for RigNodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidPrefix => f.write_str("invalid service prefix (not a valid file name)"),
            Self::InvalidName => f.write_str("invalid iceoryx2 node name"),
            Self::Create(e) => write!(f, "creating the iceoryx2 node: {e:?}"),
        }
    }
}

impl core::error::Error for RigNodeError {}

impl RigNodeError {
    /// True when the operating system refused access.
    pub fn is_permission(&self) -> bool {
        *self == Self::Create(NodeCreationFailure::InsufficientPermissions)
    }
}

/// Create a node on `prefix`, optionally named, then restrict the prefix's
/// shared memory to its owner.
pub fn rig_node(
    prefix: &str,
    name: Option<&str>,
    signals: SignalHandlingMode,
) -> Result<Node<ipc::Service>, RigNodeError> {
    let config = config_with_prefix(prefix).map_err(|_| RigNodeError::InvalidPrefix)?;
    let mut builder = NodeBuilder::new().config(&config).signal_handling_mode(signals);
    if let Some(n) = name {
        builder = builder.name(&NodeName::new(n).map_err(|_| RigNodeError::InvalidName)?);
    }
    let node = builder.create::<ipc::Service>().map_err(RigNodeError::Create)?;
    restrict_to_owner(prefix);
    Ok(node)
}

/// Make every file of `prefix` in /dev/shm that this user owns readable and
/// writable by this user only. Returns how many files it changed. Best
/// effort: a file that vanishes meanwhile is skipped.
#[allow(unsafe_code)]
pub fn restrict_to_owner(prefix: &str) -> usize {
    // SAFETY: geteuid(2) has no preconditions and cannot fail.
    let me = unsafe { libc::geteuid() };
    let Ok(dir) = std::fs::read_dir(SHM_DIR) else { return 0 };
    let mut changed = 0;
    for entry in dir.flatten() {
        if !entry.file_name().as_encoded_bytes().starts_with(prefix.as_bytes()) {
            continue;
        }
        let Ok(meta) = entry.metadata() else { continue };
        if meta.uid() == me && meta.mode() & 0o077 != 0 {
            let mode = meta.mode() & 0o700;
            if std::fs::set_permissions(entry.path(), std::fs::Permissions::from_mode(mode)).is_ok() {
                changed += 1;
            }
        }
    }
    changed
}

/// Files of `prefix` in /dev/shm that someone other than their owner may
/// open (what a security check looks for).
pub fn files_open_to_others(prefix: &str) -> Vec<(String, u32)> {
    let Ok(dir) = std::fs::read_dir(SHM_DIR) else { return Vec::new() };
    dir.flatten()
        .filter(|e| e.file_name().as_encoded_bytes().starts_with(prefix.as_bytes()))
        .filter_map(|e| {
            let mode = e.metadata().ok()?.mode() & 0o777;
            (mode & 0o077 != 0).then(|| (e.file_name().to_string_lossy().into_owned(), mode))
        })
        .collect()
}

/// Remove the per-prefix node-counter segment iceoryx2 leaves in /dev/shm,
/// once no node on `prefix` is alive (tests and benches use a prefix per
/// run). Returns whether it was removed. iceoryx2 0.10 offers this only
/// in its `testing` module; this is the one place UPM calls it.
#[allow(unsafe_code)]
pub fn remove_prefix_segment(prefix: &str) -> bool {
    let Ok(config) = config_with_prefix(prefix) else { return false };
    // Every live node counts (dead nodes' files are cleaned up on the way).
    if !crate::node_list::live_nodes(prefix, "").is_ok_and(|nodes| nodes.is_empty()) {
        return false;
    }
    // SAFETY: no node on this prefix is alive (checked just above); the
    // prefix is one per rig, test or bench run, so no new node joins it.
    unsafe { iceoryx2::testing::remove_global_mgmt_segment::<ipc::Service>(&config) }.unwrap_or(false)
}

/// A service prefix no other rig, test or bench run uses at the same time:
/// `head`, this process's id and the clock's nanoseconds
/// (`upmt_vision_4242_123456789_`). Pair it with [`remove_prefix_segment`].
pub fn unique_prefix(head: &str) -> String {
    let nanos =
        std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.subsec_nanos());
    format!("{head}_{}_{nanos}_", std::process::id())
}
