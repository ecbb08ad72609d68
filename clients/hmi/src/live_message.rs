//! What the page shows, as one JSON text built [`UPDATES_PER_SECOND`]
//! times a second from the rig's newest snapshot and handed to every
//! WebSocket at once (a `watch` channel: a slow browser skips to the
//! newest, nobody waits for it). docs/hmi.md gives the format.

use std::sync::Arc;
use std::time::Duration;

use axum::extract::ws::Utf8Bytes;
use ipc_types::{CoreState, LatencyPercentiles, PartState, SHAPE_DISC, SHAPE_POLYGON};
use serde_json::{Value, json};
use tokio::sync::watch;
use upm_rig_client::rig_view::{RigSnapshot, RigView};

use crate::trails::Trails;

pub const UPDATES_PER_SECOND: u32 = 10;

/// A part's outline in its own frame.
fn outline(p: &PartState) -> Value {
    match p.shape {
        SHAPE_DISC => json!({ "disc": p.radius }),
        SHAPE_POLYGON => json!({ "polygon": p.polygon() }),
        _ => json!("point"),
    }
}

fn p99_us(p: &LatencyPercentiles) -> f64 {
    p.p99_ns as f64 / 1e3
}

/// The page's state, from `s` and the trails so far.
pub fn live_json(s: &RigSnapshot, trails: &Trails) -> Value {
    let t = s.telemetry.as_ref();
    let parts: Vec<Value> = s
        .parts
        .as_deref()
        .map(|ps| ps.parts())
        .unwrap_or_default()
        .iter()
        .map(|p| {
            json!({
                "id": p.id, "class": p.class, "x": p.x, "y": p.y, "theta": p.theta,
                "outline": outline(p),
                "trail": trails.of(p.id).collect::<Vec<_>>(),
            })
        })
        .collect();
    let poses: Vec<Value> = s
        .poses
        .iter()
        .map(|p| json!({ "class": p.class, "part_id": p.part_id, "ready": p.ready, "x": p.x, "y": p.y, "theta": p.theta }))
        .collect();
    // A feed cell counts its parts itself (as `upm status` shows them);
    // without one, the parts vision sees.
    let on_plate = s.feed.as_ref().map_or(parts.len() as u64, |f| u64::from(f.on_plate));
    let health = match t.and_then(|t| t.health().map(|h| (h, t.health_detail_str()))) {
        Some(((source, cause), detail)) => json!({
            "ok": source == ipc_types::HealthSource::Ok && s.state != CoreState::Fault,
            "source": source.as_str(), "cause": cause.as_str(), "detail": detail, "text": s.health,
        }),
        None => {
            json!({ "ok": false, "source": "unknown", "cause": "unknown", "detail": "", "text": s.health })
        }
    };
    json!({
        "state": s.state.as_str(),
        "hold": s.state == CoreState::Hold,
        "health": health,
        "counters": {
            "parts_on_plate": on_plate,
            "picked": s.picked,
            "parts_per_minute": s.parts_per_minute,
            "lost": s.lost,
            "holds": t.map_or(0, |t| t.counters.hold_events),
            "fault_holds": t.map_or(0, |t| t.counters.fault_holds),
            "driver_faults": t.map_or(0, |t| t.counters.driver_faults),
            "overruns": t.map_or(0, |t| t.counters.overruns),
        },
        "latency_us": {
            "motor_wakeup_p99": t.map(|t| p99_us(&t.latency.motor_wakeup)),
            "solver_p99": t.map(|t| p99_us(&t.latency.solver)),
        },
        "recipe": { "name": s.recipe, "path": s.recipe_path, "error": s.recipe_error },
        "plate": { "half_extent": s.plate_half_extent, "x": t.map(|t| t.plate_x), "y": t.map(|t| t.plate_y), "theta": t.map(|t| t.plate_theta) },
        "parts": parts,
        "poses": poses,
        "invalid_messages": s.invalid_messages,
    })
}

/// Build the page's state from `view` until `stop` fires; each open page
/// sees the newest.
pub async fn publish(view: Arc<RigView>, out: Arc<watch::Sender<Utf8Bytes>>, stop: watch::Receiver<bool>) {
    let mut stop = stop;
    let mut tick = tokio::time::interval(Duration::from_secs(1) / UPDATES_PER_SECOND);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let mut trails = Trails::default();
    let mut last_parts_seq = None;
    loop {
        tokio::select! {
            _ = tick.tick() => {}
            _ = stop.changed() => break,
        }
        let s = view.snapshot();
        if let Some(ps) = s.parts.as_deref().filter(|ps| Some(ps.seq) != last_parts_seq) {
            last_parts_seq = Some(ps.seq);
            trails.add(ps);
        }
        // Only when someone watches: no browser, no work.
        if out.receiver_count() > 0 {
            out.send_replace(Utf8Bytes::from(live_json(&s, &trails).to_string()));
        }
    }
}
