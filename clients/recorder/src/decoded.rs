//! The decoded companion of each message: JSON that Foxglove, PlotJuggler
//! or `mcap cat --json` show as fields, with a JSON schema inferred from
//! the same code, so the two never drift. Only the used entries of a
//! counted message are shown (a corrupt `count` is clamped); codes are
//! shown as names where the protocol has one.

use ipc_types::{
    CoreCommand, CoreState, ExplicitSchedule, ExplicitSlot, FeedStatus, ForceEntry, ForceRequest,
    FrameHeader, LatencyPercentiles, LineStatus, PartState, PartStates, PickCommand, PickEvent,
    PickPoseState, RECIPE_PATH_BYTES, REJECT_REASONS, RecipeCommand, RejectReason, Rejection, RigCenter,
    RigInfo, Schedule, ScheduleSlot, Telemetry,
};
use serde_json::{Map, Value, json};

/// A message with a decoded form.
pub trait Decoded: Sized {
    fn decoded(&self) -> Value;
    /// A message with one entry in each list, to infer the schema from.
    fn sample() -> Self;
}

fn code_name(name: Option<&'static str>, code: u32) -> Value {
    name.map_or_else(|| json!(format!("unknown ({code})")), |n| json!(n))
}

impl Decoded for PartStates {
    fn decoded(&self) -> Value {
        let parts: Vec<Value> = self
            .parts()
            .iter()
            .map(|p| {
                let mut v = json!({"id": p.id, "class": p.class, "friction_class": p.friction_class,
                       "x": p.x, "y": p.y, "theta": p.theta, "vx": p.vx, "vy": p.vy, "omega": p.omega,
                       "shape": p.shape});
                // Only the fields the outline uses.
                match p.shape {
                    ipc_types::SHAPE_DISC => v["radius"] = json!(p.radius),
                    ipc_types::SHAPE_POLYGON => v["vertices"] = json!(p.polygon()),
                    _ => {}
                }
                v
            })
            .collect();
        json!({"protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "count": self.count, "parts": parts})
    }
    fn sample() -> Self {
        let mut m = Self::new();
        let _ = m.push(PartState::ZERO);
        m
    }
}

impl Decoded for ForceRequest {
    fn decoded(&self) -> Value {
        let entries: Vec<Value> = self
            .entries()
            .iter()
            .map(|e| {
                json!({"part_id": e.part_id, "force_flag": e.force_flag, "curl_flag": e.curl_flag,
                       "fx": e.fx, "fy": e.fy, "curl": e.curl})
            })
            .collect();
        json!({"protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "deadline_ns": self.deadline_ns, "count": self.count, "entries": entries})
    }
    fn sample() -> Self {
        let mut m = Self::new();
        let _ = m.push(ForceEntry::ZERO);
        m
    }
}

impl Decoded for ExplicitSchedule {
    fn decoded(&self) -> Value {
        let slots: Vec<Value> =
            self.slots().iter().map(|s| json!({"center_index": s.center_index, "k": s.k})).collect();
        json!({"protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "count": self.count, "slots": slots})
    }
    fn sample() -> Self {
        let mut m = Self::new();
        let _ = m.push(ExplicitSlot::new(0, 0.0));
        m
    }
}

impl Decoded for CoreCommand {
    fn decoded(&self) -> Value {
        json!({"protocol_version": self.protocol_version, "command": self.command, "seq": self.seq,
               "stamp_ns": self.stamp_ns})
    }
    fn sample() -> Self {
        Self::new(0, 0, 0)
    }
}

impl Decoded for PickCommand {
    fn decoded(&self) -> Value {
        json!({"protocol_version": self.protocol_version, "pose": self.pose, "seq": self.seq,
               "stamp_ns": self.stamp_ns, "part_id": self.part_id})
    }
    fn sample() -> Self {
        Self::new(0, 0, 0, 0)
    }
}

impl Decoded for RecipeCommand {
    /// The path as text: its used bytes (a corrupt `path_len` clamped),
    /// invalid UTF-8 replaced.
    fn decoded(&self) -> Value {
        let used = &self.path[..(self.path_len as usize).min(RECIPE_PATH_BYTES)];
        json!({"protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "path_len": self.path_len, "path": String::from_utf8_lossy(used)})
    }
    fn sample() -> Self {
        Self::new("/", 0, 0).expect("the root is an absolute path")
    }
}

impl Decoded for LineStatus {
    fn decoded(&self) -> Value {
        let refused: Map<String, Value> =
            self.refusals().iter().map(|(name, n)| ((*name).to_owned(), json!(n))).collect();
        json!({"protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "line_pid": self.line_pid, "opcua_sessions": self.opcua_sessions,
               "modbus_connections": self.modbus_connections, "refused": refused,
               "refused_total": self.total_refusals(), "picks_sent": self.picks_sent,
               "recipes_loaded": self.recipes_loaded, "recipes_refused": self.recipes_refused})
    }
    fn sample() -> Self {
        Self::new()
    }
}

impl Decoded for Schedule {
    fn decoded(&self) -> Value {
        let slots: Vec<Value> = self
            .slots()
            .iter()
            .map(|s| json!({"center_index": s.center_index, "x": s.x, "y": s.y, "k": s.k}))
            .collect();
        json!({"protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "cycle": self.cycle, "solve_time_ns": self.solve_time_ns, "parts_seq": self.parts_seq,
               "parts_stamp_ns": self.parts_stamp_ns, "request_stamp_ns": self.request_stamp_ns,
               "residual": self.residual,
               "condition": finite_or_null(self.condition), "rank": self.rank, "saturated": self.saturated,
               "at_bound": self.at_bound, "count": self.count, "slots": slots})
    }
    fn sample() -> Self {
        let mut m = Self::new();
        let _ = m.push(ScheduleSlot::ZERO);
        m
    }
}

impl Decoded for RigInfo {
    fn decoded(&self) -> Value {
        let centers: Vec<Value> =
            self.centers().iter().map(|c| json!({"x": c.x, "y": c.y, "k_bound": c.k_bound})).collect();
        json!({"protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "core_pid": self.core_pid, "cycle_slots": self.cycle_slots, "class_count": self.class_count,
               "friction_class_count": self.friction_class_count, "slot_ticks": self.slot_ticks,
               "cycle_period_ns": self.cycle_period_ns, "tick_hz": self.tick_hz,
               "vision_frame_hz": self.vision_frame_hz, "mu_m_g": self.mu_m_g,
               "plate_half_extent": self.plate_half_extent, "k_max": self.k_max,
               "max_part_force_n": self.max_part_force_n, "max_part_force_at": self.max_part_force_at,
               "keep_out_m": self.keep_out_m, "saturation_tolerance": self.saturation_tolerance,
               "saturation_floor": self.saturation_floor, "parts_max_age_ms": self.parts_max_age_ms,
               "request_max_age_ms": self.request_max_age_ms, "max_future_skew_ms": self.max_future_skew_ms,
               "prefix": self.prefix_str(), "count": self.count, "centers": centers})
    }
    fn sample() -> Self {
        let mut m = Self::new();
        let _ = m.push(RigCenter::ZERO);
        m
    }
}

impl Decoded for FeedStatus {
    fn decoded(&self) -> Value {
        let poses: Vec<Value> = self
            .poses()
            .iter()
            .map(|p| {
                json!({"class": p.class, "part_id": p.part_id, "ready": p.ready, "x": p.x, "y": p.y,
                       "theta": p.theta})
            })
            .collect();
        let recent: Vec<Value> = self
            .recent()
            .iter()
            .map(|p| {
                json!({"number": p.number, "part_id": p.part_id, "class": p.class, "pose": p.pose,
                       "time_s": p.time_s, "position_error_m": p.position_error_m,
                       "angle_error_rad": p.angle_error_rad, "on_plate_s": p.on_plate_s})
            })
            .collect();
        json!({"protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "arrived": self.arrived, "picked": self.picked, "lost": self.lost,
               "arrivals_blocked": self.arrivals_blocked, "on_plate": self.on_plate, "stuck": self.stuck,
               "collisions": self.collisions, "time_s": self.time_s, "robot_busy_s": self.robot_busy_s,
               "stuck_after_s": self.stuck_after_s, "recent_count": self.recent_count, "recent": recent,
               "count": self.count, "poses": poses})
    }
    fn sample() -> Self {
        let mut m = Self::new();
        let _ = m.push(PickPoseState::ZERO);
        m.push_pick(PickEvent::ZERO);
        m
    }
}

/// JSON has no ∞ or NaN: shown as null.
fn finite_or_null(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn latency(p: &LatencyPercentiles) -> Value {
    let us = |ns: u64| ns as f64 / 1e3;
    json!({"p50_us": us(p.p50_ns), "p99_us": us(p.p99_ns), "p999_us": us(p.p999_ns), "max_us": us(p.max_ns),
           "samples": p.samples})
}

/// The core's latency figures alone (the live view's latency panel).
pub fn latencies(t: &Telemetry) -> Value {
    let l = &t.latency;
    json!({"stamp_ns": t.stamp_ns, "motor_wakeup": latency(&l.motor_wakeup), "solver": latency(&l.solver),
           "ipc_vision_to_core": latency(&l.ipc_vision_to_core),
           "frame_to_schedule": latency(&l.frame_to_schedule)})
}

impl Decoded for Telemetry {
    fn decoded(&self) -> Value {
        let c = &self.counters;
        let by_reason: Map<String, Value> = (0..REJECT_REASONS)
            .filter_map(|i| {
                let r = RejectReason::from_code(i as u32)?;
                Some((r.as_str().to_owned(), json!(self.rejected_by_reason[i])))
            })
            .collect();
        let d = &self.driver;
        json!({
            "protocol_version": self.protocol_version, "seq": self.seq, "stamp_ns": self.stamp_ns,
            "state": code_name(self.core_state().map(CoreState::as_str), self.state), "cycle": self.cycle,
            "plate": {"x": self.plate_x, "y": self.plate_y, "theta": self.plate_theta},
            "counters": {"ticks": c.ticks, "overruns": c.overruns, "hold_events": c.hold_events,
                "schedule_swaps": c.schedule_swaps, "rejected_parts": c.rejected_parts,
                "rejected_requests": c.rejected_requests, "rt_thread_allocations": c.rt_thread_allocations,
                "driver_faults": c.driver_faults, "driver_clamped": c.driver_clamped,
                "driver_rejected": c.driver_rejected, "fault_holds": c.fault_holds, "resumes": c.resumes},
            "parts_age_ms": finite_or_null(self.parts_age_ms), "request_age_ms": finite_or_null(self.request_age_ms),
            "latency": latencies(self),
            "realtime_flags": self.realtime_flags,
            "rejected_by_reason": by_reason,
            "health_detail": self.health_detail_str(),
            "driver": {"kind": code_name(d.kind_str(), d.kind), "state": code_name(d.state_str(), d.state),
                "faults": d.faults.to_vec(), "lost_frames": d.lost_frames, "bad_frames": d.bad_frames,
                "sync0_phase_ns": d.sync0_phase_ns},
        })
    }
    fn sample() -> Self {
        Self::new()
    }
}

impl Decoded for Rejection {
    fn decoded(&self) -> Value {
        json!({"protocol_version": self.protocol_version,
               "kind": code_name(self.kind().map(|k| k.as_str()), self.kind), "seq": self.seq,
               "message_stamp_ns": self.message_stamp_ns, "stamp_ns": self.stamp_ns,
               "parts_seq": self.parts_seq, "parts_stamp_ns": self.parts_stamp_ns,
               "reason": code_name(self.reason().map(|r| r.as_str()), self.reason), "detail": self.detail_str()})
    }
    fn sample() -> Self {
        Self::new(ipc_types::RejectedKind::PartStates, 0, 0, 0, RejectReason::Empty, format_args!(""))
    }
}

impl Decoded for FrameHeader {
    fn decoded(&self) -> Value {
        json!({"protocol_version": self.protocol_version, "pixel_format": self.pixel_format, "width": self.width,
               "height": self.height, "stride": self.stride, "seq": self.seq, "stamp_ns": self.stamp_ns,
               "exposure_ns": self.exposure_ns})
    }
    fn sample() -> Self {
        Self::default()
    }
}

/// A JSON schema describing `v`'s shape (integers, numbers, strings,
/// objects with every key required, lists typed by their first element).
pub fn schema_of(v: &Value) -> Value {
    match v {
        Value::Null => json!({"type": ["number", "null"]}),
        Value::Bool(_) => json!({"type": "boolean"}),
        // A float may be shown as null (∞, NaN: `finite_or_null`).
        Value::Number(n) if n.is_f64() => json!({"type": ["number", "null"]}),
        Value::Number(_) => json!({"type": "integer"}),
        Value::String(_) => json!({"type": "string"}),
        Value::Array(a) => json!({"type": "array", "items": a.first().map_or(json!({}), schema_of)}),
        Value::Object(o) => {
            let props: Map<String, Value> = o.iter().map(|(k, v)| (k.clone(), schema_of(v))).collect();
            json!({"type": "object", "properties": props})
        }
    }
}

/// The JSON schema of `T`'s decoded form.
pub fn schema<T: Decoded>() -> Value {
    schema_of(&T::sample().decoded())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_corrupt_count_is_clamped_and_codes_have_names() {
        let mut m = PartStates::sample();
        m.count = u32::MAX;
        let v = m.decoded();
        assert_eq!(v["parts"].as_array().map(Vec::len), Some(ipc_types::MAX_PARTS));
        let mut r = Rejection::sample();
        r.reason = 9999;
        assert_eq!(r.decoded()["reason"], json!("unknown (9999)"));
        let s = schema::<Schedule>();
        assert_eq!(s["properties"]["slots"]["items"]["properties"]["k"]["type"], json!(["number", "null"]));
        assert_eq!(s["properties"]["seq"]["type"], json!("integer"));
    }

    #[test]
    fn a_feed_status_shows_its_used_poses_and_picks() {
        let mut m = FeedStatus::sample();
        m.picked = 3;
        m.recent[0].number = 3;
        m.poses[0].theta = f64::NAN;
        let v = m.decoded();
        assert_eq!((v["picked"].clone(), v["recent"][0]["number"].clone()), (json!(3), json!(3)));
        assert_eq!(v["poses"][0]["theta"], Value::Null, "JSON has no NaN");
        (m.count, m.recent_count) = (u32::MAX, 0);
        let v = m.decoded();
        assert_eq!(v["poses"].as_array().map(Vec::len), Some(ipc_types::MAX_PICK_POSES));
        assert_eq!(v["recent"].as_array().map(Vec::len), Some(0));
        let s = schema::<FeedStatus>();
        assert_eq!(s["properties"]["recent"]["items"]["properties"]["number"]["type"], json!("integer"));
        assert_eq!(s["properties"]["poses"]["items"]["properties"]["x"]["type"], json!(["number", "null"]));
    }

    #[test]
    fn a_recipe_shows_its_path_as_text() {
        let m = RecipeCommand::new("/srv/recipes/gears.toml", 7, 123).expect("absolute");
        assert_eq!(
            m.decoded(),
            json!({"protocol_version": ipc_types::PROTOCOL_VERSION, "seq": 7, "stamp_ns": 123, "path_len": 23,
                   "path": "/srv/recipes/gears.toml"})
        );
        let mut bad = m;
        (bad.path_len, bad.path[1]) = (u32::MAX, 0xFF);
        let v = bad.decoded();
        assert_eq!(v["path_len"], json!(u32::MAX));
        let path = v["path"].as_str().expect("text");
        assert!(path.starts_with("/\u{FFFD}rv/recipes/gears.toml\0"), "clamped, lossy: {path:?}");
        let s = schema::<RecipeCommand>();
        assert_eq!(s["properties"]["path"]["type"], json!("string"));
        assert_eq!(s["properties"]["path_len"]["type"], json!("integer"));
    }

    #[test]
    fn a_line_status_shows_its_refusals_by_name() {
        let mut m = LineStatus::sample();
        (m.line_pid, m.seq, m.opcua_sessions, m.access_denied, m.modbus_bad_frames) = (42, 3, 2, 5, 1);
        let v = m.decoded();
        assert_eq!((v["line_pid"].clone(), v["opcua_sessions"].clone()), (json!(42), json!(2)));
        assert_eq!(v["refused"]["access_denied"], json!(5));
        assert_eq!(v["refused"]["modbus_bad_frames"], json!(1));
        assert_eq!(v["refused"].as_object().map(Map::len), Some(8));
        assert_eq!(v["refused_total"], json!(6));
        let s = schema::<LineStatus>();
        assert_eq!(s["properties"]["refused"]["properties"]["login_failures"]["type"], json!("integer"));
    }

    #[test]
    fn a_pick_shows_its_pose_and_part() {
        let v = PickCommand::new(3, 42, 7, 123).decoded();
        assert_eq!(
            v,
            json!({"protocol_version": ipc_types::PROTOCOL_VERSION, "pose": 3, "seq": 7, "stamp_ns": 123,
                   "part_id": 42})
        );
        let s = schema::<PickCommand>();
        for field in ["protocol_version", "pose", "seq", "stamp_ns", "part_id"] {
            assert_eq!(s["properties"][field]["type"], json!("integer"), "{field}");
        }
    }
}
