//! `upm status [--json]`: the newest telemetry of the core on a prefix
//! (DESIGN.md §7).

use std::time::{Duration, Instant};

use anyhow::bail;
use iceoryx2::prelude::*;
use ipc_types::ports::{config_with_prefix, open_pub_sub};
use ipc_types::rig_node::rig_node;
use ipc_types::{LatencyPercentiles, Telemetry, ValidationLimits, monotonic_now_ns, service_names};
use serde_json::{Value, json};

/// Wait up to `timeout` for a telemetry sample of the core on `prefix`.
pub fn read_telemetry(prefix: &str, timeout: Duration) -> anyhow::Result<Telemetry> {
    let node = rig_node(prefix, None, SignalHandlingMode::Disabled)?;
    let sub = open_pub_sub::<Telemetry>(&node, service_names::TELEMETRY)?
        .subscriber_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("telemetry subscriber: {e:?}"))?;
    let start = Instant::now();
    let mut newest: Option<Telemetry> = None;
    while start.elapsed() < timeout {
        while let Some(s) = sub.receive().map_err(|e| anyhow::anyhow!("receiving telemetry: {e:?}"))? {
            newest = Some(*s.payload());
        }
        if let Some(t) = newest {
            let limits = ValidationLimits::new([f64::INFINITY; 2], monotonic_now_ns());
            t.validate(&limits).map_err(|e| anyhow::anyhow!("invalid telemetry from the core: {e}"))?;
            return Ok(t);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    bail!("no upm-core is running on service prefix {prefix:?} (no telemetry within {timeout:?})")
}

fn us(p: &LatencyPercentiles) -> Value {
    let f = |ns: u64| ns as f64 / 1e3;
    json!({ "p50": f(p.p50_ns), "p99": f(p.p99_ns), "p999": f(p.p999_ns), "max": f(p.max_ns), "samples": p.samples })
}

/// The `upm status --json` document.
pub fn to_json(t: &Telemetry) -> Value {
    let flag = |b: u32| t.realtime_flags & b != 0;
    json!({
        "state": t.core_state().map_or("unknown", |s| s.as_str()),
        "cycle": t.cycle,
        "ages_ms": { "parts": t.parts_age_ms, "request": t.request_age_ms },
        "rejected": { "parts": t.counters.rejected_parts, "requests": t.counters.rejected_requests },
        "processes": { "core": t.core_pid, "vision": t.vision_pid, "planner": t.planner_pid },
        "latency_us": {
            "motor_wakeup": us(&t.latency.motor_wakeup),
            "solver": us(&t.latency.solver),
            "ipc_vision_to_core": us(&t.latency.ipc_vision_to_core),
            "frame_to_schedule": us(&t.latency.frame_to_schedule),
        },
        "counters": {
            "ticks": t.counters.ticks,
            "overruns": t.counters.overruns,
            "hold_events": t.counters.hold_events,
            "schedule_swaps": t.counters.schedule_swaps,
            "rt_thread_allocations": t.counters.rt_thread_allocations,
        },
        "plate": { "x": t.plate_x, "y": t.plate_y, "theta": t.plate_theta },
        "realtime": {
            "memory_locked": flag(Telemetry::RT_MEMORY_LOCKED),
            "motor_fifo": flag(Telemetry::RT_MOTOR_FIFO),
            "solver_fifo": flag(Telemetry::RT_SOLVER_FIFO),
            "motor_pinned": flag(Telemetry::RT_MOTOR_PINNED),
            "receiver_fifo": flag(Telemetry::RT_RECEIVER_FIFO),
            "allocations_counted": flag(Telemetry::RT_ALLOCATIONS_COUNTED),
        },
    })
}

/// A few human-readable lines.
pub fn to_text(t: &Telemetry) -> String {
    let rt = t.realtime_flags
        & (Telemetry::RT_MEMORY_LOCKED | Telemetry::RT_MOTOR_FIFO | Telemetry::RT_SOLVER_FIFO)
        == (Telemetry::RT_MEMORY_LOCKED | Telemetry::RT_MOTOR_FIFO | Telemetry::RT_SOLVER_FIFO);
    let w = &t.latency.motor_wakeup;
    format!(
        "state {}  cycle {}  ticks {}  overruns {}  holds {}\n\
         ages: parts {:.1} ms, request {:.1} ms;  rejected: parts {}, requests {}\n\
         motor wake-up µs: p50 {:.1}  p99 {:.1}  p99.9 {:.1}  max {:.1}\n\
         real-time: {}  rt allocations: {}  core pid {}",
        t.core_state().map_or("unknown", |s| s.as_str()),
        t.cycle,
        t.counters.ticks,
        t.counters.overruns,
        t.counters.hold_events,
        t.parts_age_ms,
        t.request_age_ms,
        t.counters.rejected_parts,
        t.counters.rejected_requests,
        w.p50_ns as f64 / 1e3,
        w.p99_ns as f64 / 1e3,
        w.p999_ns as f64 / 1e3,
        w.max_ns as f64 / 1e3,
        if rt { "yes" } else { "NO (not real-time: no SCHED_FIFO or no locked memory)" },
        t.counters.rt_thread_allocations,
        t.core_pid,
    )
}

/// Remove the per-prefix segment iceoryx2 keeps in /dev/shm after every
/// node on the prefix is gone (benches use a prefix per run).
pub fn remove_prefix_segment(prefix: &str) {
    if let Ok(config) = config_with_prefix(prefix) {
        // SAFETY: called only after every node on this prefix has ended.
        let _ = unsafe { iceoryx2::testing::remove_global_mgmt_segment::<ipc::Service>(&config) };
    }
}
