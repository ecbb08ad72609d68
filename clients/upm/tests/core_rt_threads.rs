//! The real core threads (motor + solver on SCHED_FIFO when permitted) with
//! the physics simulator, fed over iceoryx2 for over a thousand cycles,
//! under a counting global allocator: the motor and solver threads make no
//! heap allocation after start-up, and the latency histograms are
//! structurally sound. No assertion on time: only counts and structure.

mod common;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use drivers::{BodyShape, PartSpec, SimConfig, Simulator};
use ipc_types::Telemetry;
use rt_core::{CoreParams, RtAllocCounter, RunOptions, alloc_count, run_core_with_truth};

#[global_allocator]
static ALLOC: RtAllocCounter = RtAllocCounter;

/// The negative control: the same counter the core test relies on does see
/// an allocation on a marked thread. (Run inside the one test: the counter
/// is process-wide, and a parallel test would pollute the core's count.)
fn counter_catches_an_allocation_on_a_marked_thread() {
    std::thread::spawn(|| {
        let (v, counted) = alloc_count::allocations_in(|| std::hint::black_box(vec![1u8; 64]));
        drop(v);
        assert!(counted > 0);
    })
    .join()
    .expect("thread");
}

#[test]
fn rt_threads_make_no_allocations_over_a_thousand_cycles() {
    rt_threads_allocate_nothing(0);
}

/// The same with sparse cycles: four slots given to the centers each
/// request needs, a center repeated where it needs more than one.
#[test]
fn rt_threads_make_no_allocations_with_sparse_cycles() {
    rt_threads_allocate_nothing(4);
}

/// The same with the solve stage's part-dynamics correction on: a plate
/// trace, part integrations and re-solves per request, each part with a
/// calibration's friction.
#[test]
fn rt_threads_make_no_allocations_with_part_dynamics() {
    let mut params = CoreParams::default();
    params.motion.cycle_slots = 4;
    params.motion.part_dynamics.steps = 2;
    params.part_friction =
        upm_motion::PartFriction::new(&[(0, 1.2), (1, 0.8)], [0.05, -0.1, 0.0, 0.1, 0.1], [1.0, 0.5])
            .expect("friction");
    rt_threads_allocate_nothing_with(params);
}

fn rt_threads_allocate_nothing(cycle_slots: usize) {
    let mut params = CoreParams::default();
    params.motion.cycle_slots = cycle_slots;
    rt_threads_allocate_nothing_with(params);
}

fn rt_threads_allocate_nothing_with(mut params: CoreParams) {
    counter_catches_an_allocation_on_a_marked_thread();
    let prefix = common::unique_prefix("rtalloc");
    params.motion.slot_ticks = 20;
    let cycle_s = 4.0 * params.motion.slot_duration();
    let duration = Duration::from_secs_f64(1500.0 * cycle_s);
    // Parts on the plate, and the simulator publishing their ground truth
    // every 10 ticks on the motor thread, as upm-core has it for the
    // simulated camera.
    let parts: Vec<PartSpec> = [[0.5, 0.0], [-0.75, 0.25], [0.0, -0.3]]
        .iter()
        .map(|&position| PartSpec {
            shape: BodyShape::Disc { radius: 0.02 },
            mass: 0.01,
            position,
            angle: 0.0,
        })
        .collect();
    let mut sim = Simulator::new(SimConfig::default(), &parts).expect("sim");
    let templates = upm_core::core_process::truth_templates(&upm_commands::config::SimParts {
        specs: parts.clone(),
        ids: vec![1, 2, 3],
        classes: vec![0, 1, 0],
        ..Default::default()
    });
    let stop = Arc::new(AtomicBool::new(false));
    let feeder = {
        let (prefix, stop) = (prefix.clone(), stop.clone());
        std::thread::spawn(move || common::feed(&prefix, Duration::from_millis(10), &stop))
    };
    let options = RunOptions { prefix: prefix.clone(), duration: Some(duration), ..RunOptions::default() };
    if std::env::var_os("UPM_ABORT_ON_RT_ALLOCATION").is_some() {
        alloc_count::abort_on_rt_allocation(true);
    }
    let truth = sim.publish_ground_truth(10, templates);
    let outputs = rt_core::SimulatorOutputs { truth: Some(truth), ..Default::default() };
    let report = run_core_with_truth(&params, sim, outputs, &options);
    stop.store(true, Ordering::Relaxed);
    feeder.join().expect("feeder");
    common::remove_prefix(&prefix);
    let report = report.expect("core ran");
    let t = &report.telemetry;
    eprintln!(
        "ticks {} cycles {} swaps {} holds {} overruns {} rejected {}+{} rt allocations {} realtime {:?}",
        t.counters.ticks,
        t.cycle,
        t.counters.schedule_swaps,
        t.counters.hold_events,
        t.counters.overruns,
        t.counters.rejected_parts,
        t.counters.rejected_requests,
        t.counters.rt_thread_allocations,
        report.realtime
    );
    assert!(report.realtime.allocations_counted, "the counting allocator is installed");
    // The defaults pin motor and solver apart, so the receiver gets SCHED_FIFO
    // on the motor's CPU exactly when the motor got both (same rights).
    let r = report.realtime;
    assert_eq!(r.receiver.fifo, r.motor.fifo && r.motor.pinned, "{r:?}");
    assert_eq!(r.receiver.fifo, r.receiver.pinned, "FIFO only together with the pin: {r:?}");
    assert_eq!(t.realtime_flags & Telemetry::RT_RECEIVER_FIFO != 0, r.receiver.fifo);
    assert!(t.cycle >= 1000, "only {} cycles ran", t.cycle);
    assert!(t.counters.schedule_swaps >= 10, "schedules were swapped in");
    assert_eq!(t.counters.rt_thread_allocations, 0, "heap allocations on the motor/solver threads");
    assert_eq!(t.counters.rejected_parts + t.counters.rejected_requests, 0);
    // The motor's feed-forward estimate ran on those cycles too.
    assert!(params.inertia_adaptation.is_some() && report.inertia.updates >= 100, "{:?}", report.inertia);

    // Histogram structure: one wake-up sample per tick, ordered percentiles.
    let h = &report.histograms;
    assert_eq!(report.dropped_samples, 0);
    assert_eq!(h.motor_wakeup.len(), t.counters.ticks);
    assert_eq!(h.motor_tick.len(), t.counters.ticks);
    for p in
        [t.latency.motor_wakeup, t.latency.solver, t.latency.ipc_vision_to_core, t.latency.frame_to_schedule]
    {
        assert!(p.is_ordered(), "{p:?}");
        assert!(p.samples > 0, "{p:?}");
    }
    assert!(h.motor_wakeup.max() < 100_000_000_000);
}
