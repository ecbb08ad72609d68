//! `upm bench ipc`: one-way PartStates latency from a vision publisher to
//! the core, against a raw iceoryx2 ping-pong of the same payload (round
//! trip halved), in the same run: event-driven against event-driven, busy
//! polling against busy polling. The solver thread's pick-up is reported
//! separately, and so is a planner's wake-up on the part states event
//! (`bench_planner_wake`).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use drivers::{SimConfig, Simulator};
use hdrhistogram::Histogram;
use ipc_types::ports::open_pub_sub;
use ipc_types::{PartStates, monotonic_now_ns};
use rt_core::{CoreParams, ReceiverWake, RunOptions, run_core};
use serde_json::{Value, json};

use crate::bench_latency::{new_histogram, summary_ns as summary, summary_row};
use crate::ipc_probe::{node, raw_event};

/// Raw iceoryx2 ping-pong of the same payload, in two views: the ping leg
/// alone (stamp → echo thread's receive, one way, like the UPM figure) and
/// the round trip / 2. The halved round trip averages a cold wake-up (the
/// echo thread slept a whole pacing period) with a hot one (the pinger went
/// to sleep microseconds before the pong), so it understates a one-way
/// wake-up. `events`: each side sleeps on an iceoryx2 listener and the
/// sender notifies (the reference for `rt.receiver = "event"`); otherwise
/// both sides busy-poll (the reference for `"spin"`).
struct RawPingPong {
    one_way: Histogram<u64>,
    half_round_trip: Histogram<u64>,
}

/// Pings before recording starts (connection set-up, caches).
const RAW_WARM_UP: u64 = 100;

/// How the echo (receiving) thread of the raw reference is scheduled.
#[derive(Clone, Copy)]
enum EchoScheduling {
    Normal,
    /// As the core's event-mode receiver: this SCHED_FIFO priority, pinned.
    LikeReceiver {
        priority: u8,
        cpu: Option<usize>,
    },
}

fn raw_ping_pong(
    samples: usize,
    events: bool,
    pace: Duration,
    echo: EchoScheduling,
) -> anyhow::Result<RawPingPong> {
    let prefix = format!("upm_bench_raw_{}_", std::process::id());
    let stop = Arc::new(AtomicBool::new(false));
    let wait = Duration::from_millis(10);
    let ponger = {
        let (prefix, stop) = (prefix.clone(), stop.clone());
        std::thread::spawn(move || -> anyhow::Result<Histogram<u64>> {
            if let EchoScheduling::LikeReceiver { priority, cpu } = echo {
                let placed = rt_core::rt_setup::make_current_thread_realtime(priority, cpu);
                anyhow::ensure!(placed.fifo, "the echo thread could not get SCHED_FIFO {priority}");
            }
            let mut one_way = new_histogram()?;
            let n = node(&prefix)?;
            let ping = open_pub_sub::<PartStates>(&n, "bench/ping")?
                .subscriber_builder()
                .create()
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            let pong = open_pub_sub::<PartStates>(&n, "bench/pong")?
                .publisher_builder()
                .create()
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            let woken = raw_event(&n, "bench/ping")?
                .listener_builder()
                .create()
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            let wake = raw_event(&n, "bench/pong")?
                .notifier_builder()
                .create()
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            let mut seen = 0u64;
            while !stop.load(Ordering::Relaxed) {
                if events {
                    woken.timed_wait(|_| {}, wait).map_err(|e| anyhow::anyhow!("{e:?}"))?;
                }
                while let Some(s) = ping.receive().map_err(|e| anyhow::anyhow!("{e:?}"))? {
                    let at = monotonic_now_ns();
                    seen += 1;
                    if seen > RAW_WARM_UP {
                        one_way.saturating_record(at.saturating_sub(s.payload().stamp_ns).max(1));
                    }
                    pong.send_copy(*s.payload()).map_err(|e| anyhow::anyhow!("{e:?}"))?;
                    if events {
                        wake.notify().map_err(|e| anyhow::anyhow!("{e:?}"))?;
                    }
                }
            }
            Ok(one_way)
        })
    };
    let n = node(&prefix)?;
    let ping = open_pub_sub::<PartStates>(&n, "bench/ping")?
        .publisher_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let pong = open_pub_sub::<PartStates>(&n, "bench/pong")?
        .subscriber_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let wake =
        raw_event(&n, "bench/ping")?.notifier_builder().create().map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let woken =
        raw_event(&n, "bench/pong")?.listener_builder().create().map_err(|e| anyhow::anyhow!("{e:?}"))?;
    std::thread::sleep(Duration::from_millis(100));
    let mut h = new_histogram()?;
    let mut msg = PartStates::new();
    let mut warm = 0;
    while (h.len() as usize) < samples {
        if ponger.is_finished() {
            break; // its error is returned below
        }
        msg.stamp_ns = monotonic_now_ns();
        ping.send_copy(msg).map_err(|e| anyhow::anyhow!("{e:?}"))?;
        if events {
            wake.notify().map_err(|e| anyhow::anyhow!("{e:?}"))?;
        }
        let give_up = msg.stamp_ns + 1_000_000_000;
        loop {
            if events {
                woken.timed_wait(|_| {}, wait).map_err(|e| anyhow::anyhow!("{e:?}"))?;
            }
            if let Some(s) = pong.receive().map_err(|e| anyhow::anyhow!("{e:?}"))? {
                let half = (monotonic_now_ns() - s.payload().stamp_ns) / 2;
                warm += 1;
                if warm > RAW_WARM_UP {
                    h.saturating_record(half.max(1));
                }
                break;
            }
            if monotonic_now_ns() > give_up {
                break;
            }
        }
        if events {
            // Paced like the feeder, not back to back: how long the
            // receiving CPU has been idle changes what its wake-up costs.
            std::thread::sleep(pace);
        }
    }
    stop.store(true, Ordering::Relaxed);
    let echoed = ponger.join().map_err(|_| anyhow::anyhow!("the ping-pong echo thread panicked"))?;
    // Ports first: alive, they would leave the prefix's files behind.
    drop((ping, pong, wake, woken, n));
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    let one_way = echoed?;
    if (h.len() as usize) < samples {
        anyhow::bail!("raw ping-pong: the echo thread stopped after {} samples", h.len());
    }
    Ok(RawPingPong { one_way, half_round_trip: h })
}

/// The feeder's period (1 kHz, a fast camera); the event references are
/// paced the same.
const FEED_PERIOD: Duration = Duration::from_millis(1);

/// Time the core gets to start and warm up before the feeder begins.
const WARM_UP: Duration = Duration::from_millis(500);

/// The core's own measurement with a feeder publishing (and notifying) at
/// 1 kHz: PartStates stamp → received by the core's receiver thread, and
/// received → validated on the solver thread.
fn upm_one_way(
    seconds: f64,
    receiver: ReceiverWake,
) -> anyhow::Result<(Histogram<u64>, Histogram<u64>, bool)> {
    let prefix = format!("upm_bench_ipc_{}_", std::process::id());
    let stop = Arc::new(AtomicBool::new(false));
    let feeder = {
        let (p, s) = (prefix.clone(), stop.clone());
        std::thread::spawn(move || {
            // Steady state only: messages queued while the core starts (its
            // solver warms up for milliseconds) are not transport latency.
            while !s.load(Ordering::Relaxed) && !ipc_types::discovery::core_running(&p).unwrap_or(false) {
                std::thread::sleep(Duration::from_millis(10));
            }
            std::thread::sleep(WARM_UP);
            crate::feeder::feed(&p, FEED_PERIOD, &s)
        })
    };
    let sim = Simulator::new(SimConfig::default(), &[]).map_err(|e| anyhow::anyhow!("{e}"))?;
    let options = RunOptions {
        prefix: prefix.clone(),
        duration: Some(Duration::from_secs_f64(seconds) + WARM_UP),
        ..RunOptions::default()
    };
    let mut params = CoreParams::default();
    params.rt.receiver = receiver;
    let report = run_core(&params, sim, &options).map_err(|e| anyhow::anyhow!("{e}"));
    stop.store(true, Ordering::Relaxed);
    let _ = feeder.join();
    ipc_types::rig_node::remove_prefix_segment(&prefix);
    let report = report?;
    let h = report.histograms;
    Ok((h.ipc_vision_to_core, h.ipc_to_solver, report.realtime.pm_qos_held))
}

/// The raw event ping-pong while a core (fed at 1 kHz) runs on its own
/// prefix: the same CPUs shared with the motor and solver threads as the
/// upm path has, to tell that sharing apart from UPM's own overhead.
fn raw_event_beside_core(echo: EchoScheduling) -> anyhow::Result<RawPingPong> {
    let done = Arc::new(AtomicBool::new(false));
    // 2000 pings paced like the feeder take ~2.2 s: the core outlives them.
    let core = {
        let done = done.clone();
        std::thread::spawn(move || {
            let r = upm_one_way(4.0, ReceiverWake::Event);
            done.store(true, Ordering::Relaxed);
            r
        })
    };
    let prefix = format!("upm_bench_ipc_{}_", std::process::id());
    while !done.load(Ordering::Relaxed) && !ipc_types::discovery::core_running(&prefix).unwrap_or(false) {
        std::thread::sleep(Duration::from_millis(10));
    }
    let up = !done.load(Ordering::Relaxed);
    std::thread::sleep(WARM_UP);
    let raw = if up {
        raw_ping_pong(2_000, true, FEED_PERIOD, echo)
    } else {
        Err(anyhow::anyhow!("the core never came up"))
    };
    // Only a control if the core ran beside the pings to the end.
    let beside = !done.load(Ordering::Relaxed);
    core.join().map_err(|_| anyhow::anyhow!("the core thread panicked"))??;
    if !beside {
        anyhow::bail!("the core ended before the control ping-pong did");
    }
    raw
}

pub fn run(seconds: f64) -> anyhow::Result<Value> {
    let rt = CoreParams::default().rt;
    // The raw references run under the idle policy the core sets for itself.
    let raw_qos = rt.cpu_dma_latency_us.map(rt_core::rt_setup::hold_cpu_dma_latency);
    let raw_held = matches!(raw_qos, Some(Ok(_)));
    let raw_event = raw_ping_pong(3_000, true, FEED_PERIOD, EchoScheduling::Normal)?;
    // The echo thread scheduled as the core's receiver is (if this process
    // may use SCHED_FIFO): what iceoryx2 gives that thread by itself.
    let like_receiver = EchoScheduling::LikeReceiver { priority: rt.receiver_priority, cpu: rt.motor_cpu };
    let raw_event_rt = match raw_ping_pong(3_000, true, FEED_PERIOD, like_receiver) {
        Ok(r) => Some(r),
        Err(e) => {
            eprintln!("bench ipc: no SCHED_FIFO reference: {e}");
            None
        }
    };
    // Paced 5× faster: shown to tell the idle-CPU wake-up cost apart.
    let raw_event_fast = raw_ping_pong(5_000, true, FEED_PERIOD / 5, EchoScheduling::Normal)?;
    let raw_busy = raw_ping_pong(10_000, false, Duration::ZERO, EchoScheduling::Normal)?;
    // The control runs its echo thread where and how the receiver runs, if
    // this process may use SCHED_FIFO.
    let beside =
        raw_event_beside_core(if raw_event_rt.is_some() { like_receiver } else { EchoScheduling::Normal })?;
    let (event, event_pickup, upm_held) = upm_one_way(seconds, ReceiverWake::Event)?;
    let (spin, spin_pickup, _) = upm_one_way(seconds, ReceiverWake::Spin)?;
    let wake = crate::bench_planner_wake::run(((seconds * 1000.0) as usize).clamp(500, 5000))?;
    drop(raw_qos);
    let (e, re, sp, rb) =
        (summary(&event), summary(&raw_event.one_way), summary(&spin), summary(&raw_busy.one_way));
    let (re_half, rb_half) = (summary(&raw_event.half_round_trip), summary(&raw_busy.half_round_trip));
    let mut v = json!({
        "host": crate::host_facts::read_all(),
        "pm_qos": { "upm": upm_held, "raw_iceoryx2": raw_held, "same_policy": upm_held == raw_held },
        "payload_bytes": size_of::<PartStates>(),
        "upm_event": e,
        "raw_iceoryx2_event": re,
        "ratio_p50_event": e.p50 / re.p50,
        "ratio_p99_event": e.p99 / re.p99,
        "raw_iceoryx2_event_half_round_trip": re_half,
        "raw_iceoryx2_event_echo_like_receiver": raw_event_rt.as_ref().map(|r| json!(summary(&r.one_way))),
        "ratio_p99_event_vs_echo_like_receiver": raw_event_rt.as_ref().map(|r| e.p99 / summary(&r.one_way).p99),
        "receiver_priority": rt.receiver_priority,
        "ratio_p99_event_vs_half_round_trip": e.p99 / re_half.p99,
        "raw_iceoryx2_event_beside_core": summary(&beside.one_way),
        "raw_iceoryx2_event_beside_core_half_round_trip": summary(&beside.half_round_trip),
        "raw_iceoryx2_event_paced_200us": summary(&raw_event_fast.one_way),
        "raw_iceoryx2_event_paced_200us_half_round_trip": summary(&raw_event_fast.half_round_trip),
        "upm_spin": sp,
        "raw_iceoryx2_busy_poll": rb,
        "raw_iceoryx2_busy_poll_half_round_trip": rb_half,
        "ratio_p50_spin": sp.p50 / rb.p50,
        "ratio_p99_spin": sp.p99 / rb.p99,
        "solver_pickup_event": summary(&event_pickup),
        "solver_pickup_spin": summary(&spin_pickup),
        "note": "upm: PartStates stamp (publisher) → received by the core's receiver thread, which then hands it wait-free to the solver thread; solver_pickup: received → validated on the solver thread (woken by the receiver through a futex). raw: ping-pong of the same payload with listeners+notify (event, paced at the feeder's 1 ms; also at 200 µs) or busy polling; the reference is the ping leg alone (stamp → echo thread's receive), *_half_round_trip the round trip / 2. planner_wake_*: PartStates stamp → published and the upm/part_states event notified (as vision does) → a planner's listener woken and the newest PartStates received, paced at 1 ms, in Rust and in Python (iceoryx2's package; null when no Python with iceoryx2 0.10 is found, planner_wake_python_run says why); raw_iceoryx2_event_wake: stamp → notify → a raw iceoryx2 event listener woken (default settings, no payload), the same pacing.",
    });
    if let (Some(all), Some(more)) = (v.as_object_mut(), wake.as_object()) {
        all.extend(more.clone());
    }
    Ok(v)
}

pub fn to_text(v: &Value) -> String {
    let row = summary_row;
    format!(
        "{}\nPM QoS held: upm {}, raw {}\none-way PartStates latency (µs), payload {} B\n{}\n{}\n{}\n{}\n{}\n{}\n{}\nratio p99 (event) {:.2}\n{}\n{}\n{}\nratio p99 (spin) {:.2}\nthen to the solver thread (futex wake):\n{}\n\
         a planner woken by the part states event (µs; JSON planner_wake_rust, planner_wake_python, \
         raw_iceoryx2_event_wake):\n{}\n{}\n{}\nratio p50 to the raw event: Rust {:.2}, Python {:.2}",
        crate::host_facts::to_text(&v["host"]),
        v["pm_qos"]["upm"],
        v["pm_qos"]["raw_iceoryx2"],
        v["payload_bytes"],
        crate::bench_latency::summary_header(),
        row("upm, event", &v["upm_event"]),
        row("raw iceoryx2, event", &v["raw_iceoryx2_event"]),
        row("  round trip / 2", &v["raw_iceoryx2_event_half_round_trip"]),
        row("raw, echo FIFO+pinned", &v["raw_iceoryx2_event_echo_like_receiver"]),
        row("raw, beside a core", &v["raw_iceoryx2_event_beside_core"]),
        row("raw, paced 200 µs", &v["raw_iceoryx2_event_paced_200us"]),
        v["ratio_p99_event"].as_f64().unwrap_or(f64::NAN),
        row("upm, spin", &v["upm_spin"]),
        row("raw iceoryx2, busy", &v["raw_iceoryx2_busy_poll"]),
        row("  round trip / 2", &v["raw_iceoryx2_busy_poll_half_round_trip"]),
        v["ratio_p99_spin"].as_f64().unwrap_or(f64::NAN),
        row("pickup (event run)", &v["solver_pickup_event"]),
        row("planner, Rust", &v["planner_wake_rust"]),
        python_row(v),
        row("raw iceoryx2 event", &v["raw_iceoryx2_event_wake"]),
        v["ratio_p50_planner_wake_rust_vs_raw_event"].as_f64().unwrap_or(f64::NAN),
        v["ratio_p50_planner_wake_python_vs_raw_event"].as_f64().unwrap_or(f64::NAN),
    )
}

/// The Python planner's row, or why it was skipped.
fn python_row(v: &Value) -> String {
    if v["planner_wake_python"].is_null() {
        format!("planner, Python        skipped: {}", v["planner_wake_python_run"]["skipped"])
    } else {
        summary_row("planner, Python", &v["planner_wake_python"])
    }
}
