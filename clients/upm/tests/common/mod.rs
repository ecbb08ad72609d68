//! Message builders and iceoryx2 isolation shared by the core tests.
#![allow(dead_code, unused_imports)]

pub use upm_cli::feeder::{PAPER_PARTS, part_states, request};

/// The RT core's binary, as `upm run` finds it: `UPM_CORE_EXE`, else
/// `upm-core` next to the `upm` under test. `cargo test --workspace` builds
/// it (with fault injection); `cargo test -p upm-cli` does not, since it is
/// another package's.
pub fn core_exe() -> std::path::PathBuf {
    if let Some(p) = std::env::var_os("UPM_CORE_EXE") {
        return p.into();
    }
    let exe = std::path::Path::new(env!("CARGO_BIN_EXE_upm")).with_file_name("upm-core");
    assert!(
        exe.is_file(),
        "{} is missing: build it with `cargo test --release -p upm-core --no-run` (or test the workspace)",
        exe.display()
    );
    exe
}

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
