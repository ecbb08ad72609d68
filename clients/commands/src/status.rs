//! `upm status [--json]`: the newest telemetry of the core on a prefix
//! (ARCHITECTURE.md §7).

use std::time::{Duration, Instant};

use anyhow::bail;
use iceoryx2::prelude::*;
use ipc_types::discovery::{NodePresence, running_rigs};
use ipc_types::rig_node::rig_node;
use ipc_types::{
    CoreCommand, FeedStatus, LatencyPercentiles, LineStatus, RecipeCommand, RejectReason, Telemetry,
    ValidationLimits, monotonic_now_ns, service_names,
};
use serde_json::{Value, json};

/// The newest `T` on `service` of the rig on `prefix`, waiting up to
/// `timeout` for one; checked whole by `validate`. None if none came.
fn read_newest<T: Copy + core::fmt::Debug + ZeroCopySend + 'static>(
    prefix: &str,
    service: &'static str,
    timeout: Duration,
    validate: impl Fn(&T, &ValidationLimits) -> Result<(), String>,
) -> anyhow::Result<Option<T>> {
    let node = rig_node(prefix, None, SignalHandlingMode::Disabled)?;
    let sub = ipc_types::ports::subscriber::<T>(&node, service)?;
    let start = Instant::now();
    let mut newest: Option<T> = None;
    while start.elapsed() < timeout && newest.is_none() {
        while let Some(s) = sub.receive().map_err(|e| anyhow::anyhow!("receiving {service}: {e:?}"))? {
            newest = Some(*s.payload());
        }
        if newest.is_none() {
            std::thread::sleep(Duration::from_millis(5));
        }
    }
    let Some(m) = newest else { return Ok(None) };
    let limits = ValidationLimits::new([f64::INFINITY; 2], monotonic_now_ns());
    validate(&m, &limits).map_err(|e| anyhow::anyhow!("invalid message on {service}: {e}"))?;
    Ok(Some(m))
}

/// Wait up to `timeout` for a telemetry sample of the core on `prefix`.
pub fn read_telemetry(prefix: &str, timeout: Duration) -> anyhow::Result<Telemetry> {
    let t = read_newest(prefix, service_names::TELEMETRY, timeout, |t: &Telemetry, l| {
        t.validate(l).map_err(|e| e.to_string())
    })?;
    t.ok_or_else(|| {
        anyhow::anyhow!(
            "no upm-core is running on service prefix {prefix:?} (no telemetry within {timeout:?})"
        )
    })
}

fn us(p: &LatencyPercentiles) -> Value {
    let f = |ns: u64| ns as f64 / 1e3;
    json!({ "p50": f(p.p50_ns), "p99": f(p.p99_ns), "p999": f(p.p999_ns), "max": f(p.max_ns), "samples": p.samples })
}

/// Seconds since a CLOCK_MONOTONIC stamp (null when 0 = absent).
fn age_s(started_ns: u64) -> Value {
    if started_ns == 0 {
        Value::Null
    } else {
        json!(monotonic_now_ns().saturating_sub(started_ns) as f64 / 1e9)
    }
}

/// Rejections by reason, only the reasons that occurred.
pub fn rejected_by_reason(t: &Telemetry) -> serde_json::Map<String, Value> {
    RejectReason::ALL
        .iter()
        .filter(|r| t.rejected_by_reason[r.index()] > 0)
        .map(|r| (r.as_str().to_owned(), json!(t.rejected_by_reason[r.index()])))
        .collect()
}

/// `ok`, or which thread or the driver, what happened and where.
fn health_json(t: &Telemetry) -> Value {
    let (source, cause) = t.health().map_or(("unknown", "unknown"), |(s, c)| (s.as_str(), c.as_str()));
    json!({ "ok": t.health_source == 0, "source": source, "cause": cause, "detail": t.health_detail_str() })
}

/// The driver's kind, bus state, faults per axis and frames lost.
pub fn driver_json(t: &Telemetry) -> Value {
    let d = &t.driver;
    json!({
        "kind": d.kind_str().unwrap_or("unknown"),
        "state": d.state_str().unwrap_or("unknown"),
        "faults": &d.faults[..],
        "lost_frames": d.lost_frames,
        "bad_frames": d.bad_frames,
        // µs after SYNC0 the last whole frame reached the reference drive;
        // null without distributed clocks.
        "sync0_phase_us": (d.sync0_phase_ns >= 0).then(|| d.sync0_phase_ns as f64 / 1e3),
    })
}

/// The feed cell's newest status; None if the core runs no cell.
pub fn read_feed(prefix: &str, timeout: Duration) -> anyhow::Result<Option<FeedStatus>> {
    read_newest(prefix, service_names::FEED, timeout, |f: &FeedStatus, l| {
        f.validate(l).map_err(|e| e.to_string())
    })
}

/// The line interface's newest counters; None if no line runs.
pub fn read_line(prefix: &str, timeout: Duration) -> anyhow::Result<Option<LineStatus>> {
    read_newest(prefix, service_names::LINE, timeout, |s: &LineStatus, l| {
        s.validate(l).map_err(|e| e.to_string())
    })
}

/// The recipe the feed cell runs (its file), as the core announced it.
pub fn read_recipe(prefix: &str, timeout: Duration) -> anyhow::Result<Option<String>> {
    let command = read_newest(prefix, service_names::RECIPE_ACTIVE, timeout, |c: &RecipeCommand, l| {
        c.validate(l).map_err(|e| e.to_string())
    })?;
    Ok(command.and_then(|c| c.path().ok().map(str::to_owned)))
}

/// `status.line`: the line interface's open connections and refusals.
pub fn line_json(s: &LineStatus) -> Value {
    let refused: serde_json::Map<String, Value> =
        s.refusals().iter().map(|&(k, v)| (k.to_owned(), json!(v))).collect();
    json!({
        "pid": s.line_pid,
        "opcua_sessions": s.opcua_sessions,
        "modbus_connections": s.modbus_connections,
        "picks_sent": s.picks_sent,
        "recipes_loaded": s.recipes_loaded,
        "recipes_refused": s.recipes_refused,
        "refused": refused,
        "refused_total": s.total_refusals(),
    })
}

/// One line: the line interface's connections and what it refused.
pub fn line_text(s: &LineStatus) -> String {
    let refused: Vec<String> =
        s.refusals().iter().filter(|(_, v)| *v > 0).map(|(k, v)| format!("{k} {v}")).collect();
    format!(
        "line: pid {}, {} OPC UA sessions, {} Modbus connections, {} picks passed on, recipes loaded {} (refused {}); refused {}: {}",
        s.line_pid,
        s.opcua_sessions,
        s.modbus_connections,
        s.picks_sent,
        s.recipes_loaded,
        s.recipes_refused,
        s.total_refusals(),
        if refused.is_empty() { "none".to_owned() } else { refused.join(", ") }
    )
}

/// `status.feed`: the cell's counters and each pick pose.
pub fn feed_json(f: &FeedStatus) -> Value {
    let poses: Vec<Value> = f
        .poses()
        .iter()
        .map(|p| {
            json!({"class": p.class, "part_id": p.part_id, "ready": p.ready == 1, "x": p.x, "y": p.y, "theta": p.theta})
        })
        .collect();
    json!({
        "time_s": f.time_s,
        "arrived": f.arrived,
        "picked": f.picked,
        "lost": f.lost,
        "on_plate": f.on_plate,
        "stuck": f.stuck,
        "stuck_after_s": f.stuck_after_s,
        "arrivals_blocked": f.arrivals_blocked,
        "collisions": f.collisions,
        "robot_busy_s": f.robot_busy_s,
        "poses": poses,
    })
}

/// One line: the cell's counters and which poses hold a part.
pub fn feed_text(f: &FeedStatus) -> String {
    let poses: Vec<String> = f
        .poses()
        .iter()
        .enumerate()
        .map(|(n, p)| match (p.part_id, p.ready) {
            (0, _) => format!("{n} free"),
            (id, 1) => format!("{n} part {id} ready"),
            (id, _) => format!("{n} part {id}"),
        })
        .collect();
    format!(
        "feed: {:.0} s, arrived {}, picked {}, lost {}, on plate {}, stuck (> {:.0} s) {}, arrivals blocked {}; poses: {}",
        f.time_s,
        f.arrived,
        f.picked,
        f.lost,
        f.on_plate,
        f.stuck_after_s,
        f.stuck,
        f.arrivals_blocked,
        poses.join(", ")
    )
}

/// The `upm status --json` document.
pub fn to_json(t: &Telemetry) -> Value {
    let flag = |b: u32| t.realtime_flags & b != 0;
    let c = &t.counters;
    let mut doc = json!({
        "state": t.core_state().map_or("unknown", |s| s.as_str()),
        "health": health_json(t),
        "cycle": t.cycle,
        "ages_ms": { "parts": t.parts_age_ms, "request": t.request_age_ms },
        "rejected": {
            "parts": c.rejected_parts,
            "requests": c.rejected_requests,
            "by_reason": rejected_by_reason(t),
        },
        "processes": {
            "core": t.core_pid,
            "vision": t.vision_pid,
            "planner": t.planner_pid,
            "vision_age_s": age_s(t.vision_started_ns),
            "planner_age_s": age_s(t.planner_started_ns),
        },
        "driver": {
            "fault_reads": c.driver_faults,
            "clamped": c.driver_clamped,
            "rejected": c.driver_rejected,
            "fault_holds": c.fault_holds,
            "resumes": c.resumes,
        },
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
            "pm_qos_held": flag(Telemetry::RT_PM_QOS_HELD),
            "allocations_counted": flag(Telemetry::RT_ALLOCATIONS_COUNTED),
        },
    });
    if let (Some(d), Value::Object(more)) =
        (doc.get_mut("driver").and_then(Value::as_object_mut), driver_json(t))
    {
        d.extend(more);
    }
    doc
}

/// A few human-readable lines.
pub fn to_text(t: &Telemetry) -> String {
    let rt = t.realtime_flags
        & (Telemetry::RT_MEMORY_LOCKED | Telemetry::RT_MOTOR_FIFO | Telemetry::RT_SOLVER_FIFO)
        == (Telemetry::RT_MEMORY_LOCKED | Telemetry::RT_MOTOR_FIFO | Telemetry::RT_SOLVER_FIFO);
    let w = &t.latency.motor_wakeup;
    let c = &t.counters;
    let health = match t.health() {
        Some((ipc_types::HealthSource::Ok, _)) => "ok".to_owned(),
        Some((s, c)) => format!("{s} {c}: {}", t.health_detail_str()),
        None => "unknown".to_owned(),
    };
    let reasons: Vec<String> = rejected_by_reason(t).iter().map(|(k, v)| format!("{k} {v}")).collect();
    let client = |pid: u32, started: u64| {
        if pid == 0 {
            "absent".to_owned()
        } else {
            format!("pid {pid}, up {:.0} s", age_s(started).as_f64().unwrap_or(0.0))
        }
    };
    format!(
        "state {}  health {}\n\
         cycle {}  ticks {}  overruns {}  holds {}\n\
         ages: parts {:.1} ms, request {:.1} ms;  rejected: parts {}, requests {}{}\n\
         driver: {} {}, axis faults {:?}, lost frames {}, bad frames {}{}\n\
         driver faults read {}, fault holds {}, resumes {}, clamped {}, rejected {}\n\
         motor wake-up µs: p50 {:.1}  p99 {:.1}  p99.9 {:.1}  max {:.1}\n\
         real-time: {}  PM QoS held: {}  rt allocations: {}\n\
         processes: core pid {}; vision {}; planner {}",
        t.core_state().map_or("unknown", |s| s.as_str()),
        health,
        t.cycle,
        c.ticks,
        c.overruns,
        c.hold_events,
        t.parts_age_ms,
        t.request_age_ms,
        c.rejected_parts,
        c.rejected_requests,
        if reasons.is_empty() { String::new() } else { format!(" ({})", reasons.join(", ")) },
        t.driver.kind_str().unwrap_or("unknown"),
        t.driver.state_str().unwrap_or("unknown"),
        t.driver.faults,
        t.driver.lost_frames,
        t.driver.bad_frames,
        if t.driver.sync0_phase_ns >= 0 {
            format!(", frames {:.1} µs after SYNC0", t.driver.sync0_phase_ns as f64 / 1e3)
        } else {
            String::new()
        },
        c.driver_faults,
        c.fault_holds,
        c.resumes,
        c.driver_clamped,
        c.driver_rejected,
        w.p50_ns as f64 / 1e3,
        w.p99_ns as f64 / 1e3,
        w.p999_ns as f64 / 1e3,
        w.max_ns as f64 / 1e3,
        if rt { "yes" } else { "NO (not real-time: no SCHED_FIFO or no locked memory)" },
        if t.realtime_flags & Telemetry::RT_PM_QOS_HELD != 0 { "yes" } else { "no" },
        c.rt_thread_allocations,
        t.core_pid,
        client(t.vision_pid, t.vision_started_ns),
        client(t.planner_pid, t.planner_started_ns),
    )
}

/// Which rig `upm status` / `upm resume` talk to when no prefix is given:
/// the only running one. Several or none is an error listing what runs.
pub fn discover_prefix() -> anyhow::Result<String> {
    let rigs = running_rigs().map_err(|e| anyhow::anyhow!("reading the running rigs: {e:?}"))?;
    match rigs.as_slice() {
        [one] => Ok(one.name.clone()),
        [] => bail!("no running upm rig found on this machine (start one with `upm run`, or pass --prefix)"),
        many => bail!("{} rigs are running, pass one with --prefix: {}", many.len(), rig_list(many)),
    }
}

/// `prefix (pid P, up N s)` for each rig.
pub fn rig_list(rigs: &[NodePresence]) -> String {
    let now = monotonic_now_ns();
    rigs.iter()
        .map(|r| {
            format!("{} (pid {}, up {:.0} s)", r.name, r.pid, now.saturating_sub(r.started_ns) as f64 / 1e9)
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Send an operator's command (`CoreCommand::RESUME`, `STOP`, `START`) to
/// the core on `prefix`.
pub fn send_command(prefix: &str, command: u32) -> anyhow::Result<()> {
    if !ipc_types::discovery::core_running(prefix).map_err(|e| anyhow::anyhow!("{e}"))? {
        bail!("no upm-core is running on service prefix {prefix:?}");
    }
    let node = rig_node(prefix, None, SignalHandlingMode::Disabled)?;
    let publisher = ipc_types::ports::publisher::<CoreCommand>(&node, service_names::CORE_COMMAND)?;
    let mut notifier =
        ipc_types::wake_event::WakeNotifier::new(&node, ipc_types::wake_event::WakeEvent::Inbox)?;
    // The core's subscriber connects to a new publisher on its next look.
    std::thread::sleep(Duration::from_millis(100));
    publisher
        .send_copy(CoreCommand::new(command, 1, monotonic_now_ns()))
        .map_err(|e| anyhow::anyhow!("sending command {command}: {e:?}"))?;
    notifier.notify();
    Ok(())
}

/// `upm status`: the core's telemetry, and where they run, the feed cell's
/// status and recipe and the line interface's counters; JSON or text.
pub fn report(prefix: &str, timeout_s: f64, as_json: bool) -> anyhow::Result<String> {
    if !(timeout_s.is_finite() && timeout_s > 0.0 && timeout_s < 3600.0) {
        bail!("--timeout must be a positive number of seconds below 3600, got {timeout_s}");
    }
    let t = read_telemetry(prefix, Duration::from_secs_f64(timeout_s))?;
    // Each published a few times a second, where it runs.
    let briefly = Duration::from_millis(300);
    let feed = read_feed(prefix, briefly)?;
    let recipe = if feed.is_some() { read_recipe(prefix, briefly)? } else { None };
    let line = read_line(prefix, briefly)?;
    if as_json {
        let mut v = to_json(&t);
        v["prefix"] = json!(prefix);
        v["feed"] = feed.as_ref().map_or(Value::Null, feed_json);
        if let (Some(r), Some(f)) = (&recipe, v["feed"].as_object_mut()) {
            f.insert("recipe".into(), json!(r));
        }
        v["line"] = line.as_ref().map_or(Value::Null, line_json);
        return Ok(serde_json::to_string_pretty(&v)?);
    }
    let mut text = format!("rig {prefix}\n{}", to_text(&t));
    if let Some(f) = &feed {
        text += &format!("\n{}", feed_text(f));
    }
    if let Some(r) = &recipe {
        text += &format!("\nrecipe: {r}");
    }
    if let Some(l) = &line {
        text += &format!("\n{}", line_text(l));
    }
    Ok(text)
}
