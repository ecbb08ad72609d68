//! Message builders and iceoryx2 isolation shared by the core tests.
#![allow(dead_code, unused_imports)]

pub use upm_cli::feeder::{PAPER_PARTS, part_states, request};

/// A service prefix no other test or rig uses.
pub fn unique_prefix(tag: &str) -> String {
    ipc_types::rig_node::unique_prefix(&format!("upmt_{tag}"))
}

/// A plain iceoryx2 node on `prefix`: no signal handling, and unlike
/// `rig_node` it leaves the prefix's file permissions as they are.
pub fn plain_node(prefix: &str) -> iceoryx2::prelude::Node<iceoryx2::prelude::ipc::Service> {
    use iceoryx2::prelude::*;
    let config = ipc_types::ports::config_with_prefix(prefix).expect("prefix");
    NodeBuilder::new()
        .config(&config)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .expect("node")
}

/// Remove the per-prefix segment iceoryx2 leaves in /dev/shm.
pub fn remove_prefix(prefix: &str) {
    ipc_types::rig_node::remove_prefix_segment(prefix);
}

/// Publish the §3.1 inputs on `prefix` every `period` until `stop`.
pub fn feed(prefix: &str, period: std::time::Duration, stop: &std::sync::atomic::AtomicBool) {
    upm_cli::feeder::feed(prefix, period, stop).expect("feeder");
}
