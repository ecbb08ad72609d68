//! One UPM process run against its services on a rig of its own: the test
//! plays the processes around it (see the README).

use std::fmt::Debug;
use std::path::PathBuf;
use std::process::Child;
use std::time::{Duration, Instant};

use iceoryx2::prelude::*;
use ipc_types::ports::Sub;

/// A rig of its own for one test. Declare it before the ports and
/// processes that use it: locals drop in reverse order, so they are gone
/// before the rig removes its shared memory.
#[derive(Debug)]
pub struct TestRig {
    pub prefix: String,
    /// `rig.toml` in a directory of its own.
    pub config: PathBuf,
    dir: PathBuf,
    node: Option<Node<ipc::Service>>,
}

impl TestRig {
    /// A unique prefix from `tag`, and the config file `toml(prefix)`.
    pub fn new(tag: &str, toml: impl FnOnce(&str) -> String) -> Self {
        let prefix = ipc_types::rig_node::unique_prefix(&format!("upmt_{tag}"));
        let dir = std::env::temp_dir().join(format!("{prefix}cfg"));
        std::fs::create_dir_all(&dir).expect("config directory");
        let config = dir.join("rig.toml");
        std::fs::write(&config, toml(&prefix)).expect("config file");
        let node = NodeBuilder::new()
            .config(&ipc_types::ports::config_with_prefix(&prefix).expect("prefix"))
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()
            .expect("node");
        Self { prefix, config, dir, node: Some(node) }
    }

    pub fn node(&self) -> &Node<ipc::Service> {
        self.node.as_ref().expect("the node lives as long as the rig")
    }

    /// Call `feed` every `period` and collect what `answers` delivers, until
    /// `n` answers arrived or `timeout` passed.
    pub fn exchange<T: Debug + Copy + ZeroCopySend>(
        answers: &Sub<T>,
        n: usize,
        timeout: Duration,
        period: Duration,
        mut feed: impl FnMut(),
    ) -> Vec<T> {
        let start = Instant::now();
        let mut got = Vec::new();
        while got.len() < n && start.elapsed() < timeout {
            feed();
            while let Some(s) = answers.receive().expect("receive") {
                got.push(*s.payload());
            }
            std::thread::sleep(period);
        }
        got
    }
}

impl Drop for TestRig {
    fn drop(&mut self) {
        drop(self.node.take());
        ipc_types::rig_node::remove_prefix_segment(&self.prefix);
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// A spawned process, stopped with SIGINT and waited for when dropped.
#[derive(Debug)]
pub struct Running(pub Child);

impl Drop for Running {
    fn drop(&mut self) {
        // SAFETY: plain kill(2) on our own child.
        unsafe { libc::kill(self.0.id() as libc::pid_t, libc::SIGINT) };
        let _ = self.0.wait();
    }
}
