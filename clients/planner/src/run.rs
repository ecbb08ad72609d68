//! The planner process loop: newest PartStates in, ForceRequest out, over
//! iceoryx2. Waits (never crashes) while no vision or core is up; exits
//! cleanly on SIGINT/SIGTERM.

use std::time::Duration;

use iceoryx2::node::NodeWaitFailure;
use iceoryx2::prelude::*;
use ipc_types::discovery::CoreWatch;
use ipc_types::rig_node::rig_node;
use ipc_types::wake_event::{WakeEvent, WakeNotifier};
use ipc_types::{ForceRequest, PartStates, RecipeCommand, monotonic_now_ns, service_names};

use crate::Planner;

/// How long a request stays valid: the core holds if no newer one arrives.
pub const REQUEST_LIFETIME_NS: u64 = 300_000_000;

/// Run `planner` on `prefix` until a signal (or `duration`); returns the
/// number of requests sent.
pub fn run_planner(
    planner: &mut dyn Planner,
    prefix: &str,
    duration: Option<Duration>,
) -> anyhow::Result<u64> {
    let node = rig_node(
        prefix,
        Some(ipc_types::discovery::PLANNER_NODE),
        SignalHandlingMode::HandleTerminationRequests,
    )?;
    let parts = ipc_types::ports::subscriber::<PartStates>(&node, service_names::PART_STATES)?;
    let requests = ipc_types::ports::publisher::<ForceRequest>(&node, service_names::FORCE_REQUEST)?;
    let recipes = ipc_types::ports::subscriber::<RecipeCommand>(&node, service_names::RECIPE_ACTIVE)?;
    let mut wake = WakeNotifier::new(&node, WakeEvent::Inbox)?;
    let start = monotonic_now_ns();
    let end = duration.map(|d| start + d.as_nanos() as u64);
    let mut first_frame: Option<u64> = None;
    let mut msg = ForceRequest::new();
    let mut sent = 0u64;
    let mut core = CoreWatch::new(prefix, Duration::from_secs(1));
    loop {
        if let Some(news) = core.poll() {
            eprintln!("upm-planner: {news}");
        }
        while let Some(r) = recipes.receive().map_err(|e| anyhow::anyhow!("receiving recipes: {e:?}"))? {
            follow_recipe(planner, r.payload());
        }
        let mut newest = None;
        while let Some(s) = parts.receive().map_err(|e| anyhow::anyhow!("receiving part states: {e:?}"))? {
            newest = Some(*s.payload());
        }
        if let Some(states) = newest {
            let t0 = *first_frame.get_or_insert(states.stamp_ns);
            let t = states.stamp_ns.saturating_sub(t0) as f64 / 1e9;
            if planner.plan(&states, t, &mut msg) {
                let now = monotonic_now_ns();
                sent += 1;
                msg.seq = sent;
                msg.stamp_ns = now;
                msg.deadline_ns = now + REQUEST_LIFETIME_NS;
                requests.send_copy(msg).map_err(|e| anyhow::anyhow!("publishing a request: {e:?}"))?;
                wake.notify();
            }
        }
        if end.is_some_and(|e| monotonic_now_ns() >= e) {
            return Ok(sent);
        }
        match node.wait(Duration::from_millis(1)) {
            Ok(()) => {}
            Err(NodeWaitFailure::Interrupt | NodeWaitFailure::TerminationRequest) => return Ok(sent),
        }
    }
}

/// Switch `planner` to the recipe the core now runs; a planner that
/// cannot follow says why (it keeps its own recipe).
fn follow_recipe(planner: &mut dyn Planner, command: &RecipeCommand) {
    let outcome = match command.path() {
        Ok(path) => planner.recipe_changed(path).map(|switched| (switched, path)),
        Err(e) => Err(e.to_string()),
    };
    match outcome {
        Ok((true, path)) => eprintln!("upm-planner: recipe changed to {path}"),
        Ok((false, _)) => {}
        Err(why) => eprintln!("upm-planner: WARNING: cannot follow the core's recipe: {why}"),
    }
}
