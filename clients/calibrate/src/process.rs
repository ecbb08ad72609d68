//! The calibration as a process on a running rig: part states in,
//! explicit schedules out, over iceoryx2; the core's rejections of them
//! stop it with the core's own words.

use std::time::{Duration, Instant};

use iceoryx2::node::NodeWaitFailure;
use iceoryx2::prelude::*;
use ipc_types::rig_node::rig_node;
use ipc_types::wake_event::{WakeEvent, WakeNotifier};
use ipc_types::{ExplicitSchedule, PartStates, Rejection, monotonic_now_ns, service_names};
use rig_config::PlateCalibration;

use crate::{CalibrateSetup, Exciter, Step};

/// Play the excitation on the rig at `prefix` and fit. Stops with an error
/// if no part states arrive for `patience`, on a signal, or if the core
/// refuses a schedule.
pub fn run_calibration(
    setup: CalibrateSetup,
    prefix: &str,
    patience: Duration,
) -> anyhow::Result<PlateCalibration> {
    let mut exciter = Exciter::new(setup)?;
    let node = rig_node(prefix, None, SignalHandlingMode::HandleTerminationRequests)?;
    let parts = ipc_types::ports::subscriber::<PartStates>(&node, service_names::PART_STATES)?;
    let rejections = ipc_types::ports::subscriber::<Rejection>(&node, service_names::REJECTION)?;
    let schedules = ipc_types::ports::publisher::<ExplicitSchedule>(&node, service_names::EXPLICIT_SCHEDULE)?;
    let mut wake = WakeNotifier::new(&node, WakeEvent::Inbox)?;
    let mut msg = ExplicitSchedule::new();
    let mut first: Option<u64> = None;
    let mut last_frame = Instant::now();
    let mut seq = 0u64;
    let mut received = Vec::new();
    loop {
        // Every frame, in order: undoing the tracker's step needs each one.
        received.clear();
        while let Some(s) = parts.receive().map_err(|e| anyhow::anyhow!("receiving part states: {e:?}"))? {
            received.push(*s.payload());
        }
        while let Some(r) =
            rejections.receive().map_err(|e| anyhow::anyhow!("receiving rejections: {e:?}"))?
        {
            if r.kind() == Some(ipc_types::RejectedKind::ExplicitSchedule) && seq > 0 {
                anyhow::bail!("the core refused the excitation: {}", r.detail_str());
            }
        }
        let mut step = None;
        for states in &received {
            last_frame = Instant::now();
            let t0 = *first.get_or_insert(states.stamp_ns);
            let t = states.stamp_ns.saturating_sub(t0) as f64 / 1e9;
            step = Some(exciter.on_frame(states, t, &mut msg)?);
            if step == Some(Step::Done) {
                break;
            }
        }
        match step {
            Some(Step::Play) => {
                seq += 1;
                msg.seq = seq;
                msg.stamp_ns = monotonic_now_ns();
                schedules.send_copy(msg).map_err(|e| anyhow::anyhow!("publishing a schedule: {e:?}"))?;
                wake.notify();
            }
            Some(Step::Done) => break,
            None => {}
        }
        if received.is_empty() && last_frame.elapsed() > patience {
            anyhow::bail!(
                "no part states on prefix {prefix} for {:.1} s: is the rig running?",
                patience.as_secs_f64()
            );
        }
        match node.wait(Duration::from_millis(1)) {
            Ok(()) => {}
            Err(NodeWaitFailure::Interrupt | NodeWaitFailure::TerminationRequest) => {
                anyhow::bail!("interrupted before the excitation was done")
            }
        }
    }
    Ok(exciter.fit()?)
}
