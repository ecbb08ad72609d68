//! Publish PartStates from a "vision" thread and receive + validate them on
//! the main thread, as the core does. Uses a prefix of its own so it never
//! talks to a running rig, and exits after `MESSAGES` messages.
//!
//! cargo run -p ipc-types --example part_states_pubsub

use core::time::Duration;

use iceoryx2::prelude::*;
use ipc_types::{PartState, PartStates, ValidationLimits, monotonic_now_ns, service_names};

const MESSAGES: u64 = 5;
/// Keeps the example off every rig's services. Fixed rather than per run:
/// iceoryx2 keeps one 16-byte segment per prefix after the nodes are gone,
/// so a per-run prefix would leave a file in /dev/shm on every run.
const PREFIX: &[u8] = b"upm_example_";
const PERIOD: Duration = Duration::from_millis(20);
const PLATE_HALF_EXTENT_M: [f64; 2] = [0.25, 0.25];

type AnyError = Box<dyn core::error::Error + Send + Sync>;

fn node(config: &Config) -> Result<Node<ipc::Service>, AnyError> {
    Ok(NodeBuilder::new().config(config).create::<ipc::Service>()?)
}

/// The vision side: one message per period, a part moving along x.
fn publish(config: &Config) -> Result<(), AnyError> {
    let node = node(config)?;
    let service = node
        .service_builder(&ServiceName::new(service_names::PART_STATES)?)
        .publish_subscribe::<PartStates>()
        .open_or_create()?;
    let publisher = service.publisher_builder().create()?;
    for seq in 0..MESSAGES {
        let mut msg = PartStates::new();
        msg.seq = seq;
        msg.stamp_ns = monotonic_now_ns();
        let x = -0.1 + 0.05 * seq as f64;
        msg.push(PartState::new(7, 0, 0, [x, 0.02, 0.0], [0.05, 0.0, 0.0]))?;
        msg.push(PartState::new(8, 1, 0, [0.0, -0.1, 1.57], [0.0; 3]))?;
        // Zero-copy: write straight into the loaned shared-memory sample.
        publisher.loan_uninit()?.write_payload(msg).send()?;
        node.wait(PERIOD)?;
    }
    Ok(())
}

fn main() -> Result<(), AnyError> {
    let mut config = Config::default();
    config.global.prefix = FileName::new(PREFIX)?;

    // The core side: subscribe before the publisher starts so nothing is missed.
    let node = node(&config)?;
    let service = node
        .service_builder(&ServiceName::new(service_names::PART_STATES)?)
        .publish_subscribe::<PartStates>()
        .open_or_create()?;
    let subscriber = service.subscriber_builder().create()?;

    let vision_config = config.clone();
    let vision = std::thread::spawn(move || publish(&vision_config));

    let mut received = 0;
    let give_up_ns = monotonic_now_ns() + 5_000_000_000;
    while received < MESSAGES && monotonic_now_ns() < give_up_ns {
        while let Some(sample) = subscriber.receive()? {
            let msg = sample.payload();
            match msg.validate(&ValidationLimits::new(PLATE_HALF_EXTENT_M, monotonic_now_ns())) {
                Ok(()) => {
                    let age_us = monotonic_now_ns().saturating_sub(msg.stamp_ns) / 1000;
                    println!("seq {} ({} µs old): {} parts", msg.seq, age_us, msg.len());
                    for p in msg.parts() {
                        println!("  id {} at ({:+.3}, {:+.3}) m, θ {:+.2} rad", p.id, p.x, p.y, p.theta);
                    }
                }
                Err(e) => println!("rejected: {e}"),
            }
            received += 1;
        }
        node.wait(Duration::from_millis(5))?;
    }
    vision.join().map_err(|_| "vision thread panicked")??;
    if received < MESSAGES {
        return Err(format!("received {received} of {MESSAGES} messages").into());
    }
    println!("done: {received} messages");
    Ok(())
}
