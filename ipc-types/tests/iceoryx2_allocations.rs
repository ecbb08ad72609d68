//! Heap allocations per call of the iceoryx2 0.10 APIs (ipc::Service) the
//! core's threads use (ARCHITECTURE.md §3). The solver thread relies on
//! `Subscriber::receive()` and `Listener::try_wait()` allocating nothing;
//! that is asserted. The other calls are measured and printed so the design
//! can be re-checked whenever iceoryx2 changes.
//!
//! The project's counting allocator counts this thread's allocations, only
//! around the measured call. `harness = false`: nothing else runs.

mod common;

use std::hint::black_box;
use std::process::ExitCode;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use common::counting_allocator::count;
use iceoryx2::prelude::*;
use ipc_types::{PartState, PartStates, service_names};

/// Steady-state calls measured per API, after the first (warm-up) call.
const CALLS: u64 = 500;

type AnyError = Box<dyn core::error::Error>;

/// Allocations of one API: on the first call and summed over `CALLS` later ones.
#[derive(Debug)]
struct Measured {
    api: &'static str,
    first_call: u64,
    steady_total: u64,
}

impl Measured {
    fn per_call(&self) -> f64 {
        self.steady_total as f64 / CALLS as f64
    }
}

/// Run `setup` (not counted) then `call` (counted), once and then `CALLS`
/// times. What `call` returns is dropped after counting stops.
fn measure<R>(
    api: &'static str,
    mut setup: impl FnMut() -> Result<(), AnyError>,
    mut call: impl FnMut() -> Result<R, AnyError>,
) -> Result<Measured, AnyError> {
    setup()?;
    let (r, first_call) = count(&mut call);
    drop(r?);
    let mut steady_total = 0;
    for _ in 0..CALLS {
        setup()?;
        let (r, n) = count(&mut call);
        drop(r?);
        steady_total += n;
    }
    Ok(Measured { api, first_call, steady_total })
}

/// A config whose prefix no other test or rig uses.
fn isolated_config(case: &str) -> Result<Config, AnyError> {
    let nanos = SystemTime::now().duration_since(UNIX_EPOCH)?.as_nanos();
    let prefix = format!("upm_alloc_{}_{nanos}_{case}_", std::process::id());
    let mut config = Config::default();
    config.global.prefix = FileName::new(prefix.as_bytes())?;
    Ok(config)
}

fn node(config: &Config) -> Result<Node<ipc::Service>, AnyError> {
    Ok(NodeBuilder::new()
        .config(config)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()?)
}

/// Check that dropping the ports and node removed the service and node,
/// then remove the prefix's last file (iceoryx2's node counter segment).
fn clean_up(config: &Config, name: &ServiceName, pattern: MessagingPattern) -> Result<(), AnyError> {
    if ipc::Service::does_exist(name, config, pattern)? {
        return Err(format!("{pattern:?} service {name} still exists after its node was dropped").into());
    }
    let mut nodes = 0;
    Node::<ipc::Service>::list(config, |_| {
        nodes += 1;
        CallbackProgression::Continue
    })?;
    if nodes != 0 {
        return Err(format!("{nodes} nodes left behind").into());
    }
    // SAFETY: the prefix is unique to this process and all its nodes are gone.
    unsafe { iceoryx2::testing::remove_global_mgmt_segment::<ipc::Service>(config) }?;
    Ok(())
}

/// A point, a disc and a polygon (a PartStates of 13336 bytes).
fn sample_payload() -> PartStates {
    let mut m = PartStates::new();
    let _ = m.push(PartState::new(1, 0, 0, [0.1, 0.0, 0.0], [0.0; 3]));
    let _ = m.push(PartState::new(2, 0, 0, [0.0, 0.1, 0.0], [0.0; 3]).with_disc(0.02));
    let triangle = [[0.02, 0.0], [-0.01, 0.015], [-0.01, -0.015]];
    if let Ok(p) = PartState::new(3, 0, 0, [-0.1, 0.0, 0.0], [0.0; 3]).with_polygon(&triangle) {
        let _ = m.push(p);
    }
    m
}

fn publish_subscribe_cases(out: &mut Vec<Measured>) -> Result<(), AnyError> {
    let config = isolated_config("pubsub")?;
    let name = ServiceName::new(service_names::PART_STATES)?;
    {
        let node = node(&config)?;
        let service = node.service_builder(&name).publish_subscribe::<PartStates>().open_or_create()?;
        let publisher = service.publisher_builder().create()?;
        let subscriber = service.subscriber_builder().create()?;
        let drain = || -> Result<(), AnyError> {
            while subscriber.receive()?.is_some() {}
            Ok(())
        };

        out.push(measure("Subscriber::receive() empty", drain, || match subscriber.receive()? {
            None => Ok(()),
            Some(_) => Err("unexpected sample".into()),
        })?);
        out.push(measure(
            "Subscriber::receive() + drop(sample)",
            || {
                publisher.send_copy(sample_payload())?;
                Ok(())
            },
            || {
                let sample = subscriber.receive()?.ok_or("no sample")?;
                // The outlines cross shared memory intact.
                let intact = black_box(*sample.payload()) == sample_payload();
                drop(sample);
                if intact { Ok(()) } else { Err("the payload changed in transit".into()) }
            },
        )?);
        // The loaned sample is returned unsent after counting stops.
        out.push(measure("Publisher::loan_uninit()", drain, || Ok(publisher.loan_uninit()?))?);
        out.push(measure("Publisher::loan_uninit() + write_payload + send()", drain, || {
            Ok(publisher.loan_uninit()?.write_payload(sample_payload()).send()?)
        })?);
        out.push(measure("Publisher::send_copy()", drain, || Ok(publisher.send_copy(sample_payload())?))?);
        drain()?;
    }
    clean_up(&config, &name, MessagingPattern::PublishSubscribe)
}

fn event_cases(out: &mut Vec<Measured>) -> Result<(), AnyError> {
    let config = isolated_config("event")?;
    let name = ServiceName::new(service_names::PART_STATES)?;
    {
        let node = node(&config)?;
        let service = node.service_builder(&name).event().open_or_create()?;
        let listener = service.listener_builder().create()?;
        let notifier = service.notifier_builder().create()?;
        let drain = || -> Result<(), AnyError> {
            listener.try_wait(|_| {})?;
            Ok(())
        };

        out.push(measure("Listener::try_wait() empty", drain, || match listener.try_wait(|_| {})? {
            0 => Ok(()),
            n => Err(format!("{n} unexpected events").into()),
        })?);
        out.push(measure(
            "Listener::try_wait() one pending event",
            || {
                notifier.notify()?;
                Ok(())
            },
            || match listener.try_wait(|e| {
                black_box(e);
            })? {
                0 => Err("pending event not seen".into()),
                _ => Ok(()),
            },
        )?);
        out.push(measure("Notifier::notify()", drain, || Ok(notifier.notify()?))?);

        let waitset = WaitSetBuilder::new()
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()?;
        let _guard = waitset.attach_notification(&listener)?;
        out.push(measure(
            "WaitSet::wait_and_process_once_with_timeout() one event",
            || {
                notifier.notify()?;
                Ok(())
            },
            || {
                let mut woke = false;
                waitset.wait_and_process_once_with_timeout(
                    |_| {
                        woke = true;
                        CallbackProgression::Continue
                    },
                    Duration::from_millis(100),
                )?;
                listener.try_wait(|_| {})?;
                if woke { Ok(()) } else { Err("waitset did not wake up".into()) }
            },
        )?);
    }
    clean_up(&config, &name, MessagingPattern::Event)
}

/// The counter must see an allocation we know happens, or every zero
/// below would be meaningless.
fn counter_sees_allocations() -> bool {
    let (v, n) = count(|| black_box(Vec::<u64>::with_capacity(16)));
    drop(v);
    n == 1
}

/// APIs the solver thread calls: they must not allocate once warm.
const MUST_NOT_ALLOCATE: [&str; 4] = [
    "Subscriber::receive() empty",
    "Subscriber::receive() + drop(sample)",
    "Listener::try_wait() empty",
    "Listener::try_wait() one pending event",
];

fn main() -> ExitCode {
    if !counter_sees_allocations() {
        eprintln!("FAILED: the counting allocator did not count a known allocation");
        return ExitCode::FAILURE;
    }
    let mut measured = Vec::new();
    if let Err(e) = publish_subscribe_cases(&mut measured).and_then(|()| event_cases(&mut measured)) {
        eprintln!("FAILED: {e}");
        return ExitCode::FAILURE;
    }
    println!(
        "iceoryx2 0.10, ipc::Service, heap allocations per call ({CALLS} steady-state calls after a first one):"
    );
    println!("{:<58} {:>10} {:>14}", "call", "first call", "steady / call");
    for m in &measured {
        println!("{:<58} {:>10} {:>14.3}", m.api, m.first_call, m.per_call());
    }
    let mut ok = true;
    for api in MUST_NOT_ALLOCATE {
        match measured.iter().find(|m| m.api == api) {
            Some(m) if m.steady_total == 0 => {}
            Some(m) => {
                eprintln!("FAILED: {api} allocated {} times in {CALLS} calls", m.steady_total);
                ok = false;
            }
            None => {
                eprintln!("FAILED: {api} was not measured");
                ok = false;
            }
        }
    }
    if ok { ExitCode::SUCCESS } else { ExitCode::FAILURE }
}
