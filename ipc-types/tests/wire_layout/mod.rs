//! Every payload's layout as the Rust compiler lays it out: the one source
//! the Python mirrors and docs/protocol.md are checked against.

use core::mem::{align_of, offset_of, size_of};

use iceoryx2::prelude::ZeroCopySend;
use ipc_types::{
    CoreCommand, CoreCounters, CoreLatencies, DriverTelemetry, ExplicitSchedule, ExplicitSlot, FeedStatus,
    ForceEntry, ForceRequest, FrameHeader, LatencyPercentiles, LineStatus, PartState, PartStates,
    PickCommand, PickEvent, PickPoseState, RecipeCommand, Rejection, RigCenter, RigInfo, Schedule,
    ScheduleSlot, Telemetry,
};

/// One field: where it is, how wide, and its Rust type (paths dropped).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    pub offset: usize,
    pub size: usize,
    pub ty: String,
}

#[derive(Debug, Clone)]
pub struct Layout {
    /// The Rust name (`PartStates`).
    pub rust: &'static str,
    /// The iceoryx2 type name (`upm::PartStates.v6`).
    pub type_name: &'static str,
    pub size: usize,
    pub align: usize,
    pub fields: Vec<Field>,
}

/// `[ipc_types::part_states::PartState; 64]` → `[PartState; 64]`.
pub fn short_type(full: &str) -> String {
    let mut s = full.to_owned();
    while let Some(i) = s.find("::") {
        let start = s[..i].rfind(|c: char| !(c.is_alphanumeric() || c == '_')).map_or(0, |j| j + 1);
        s.replace_range(start..i + 2, "");
    }
    s
}

fn type_name<T: ZeroCopySend>() -> &'static str {
    // SAFETY: only reads the name the derive generated.
    unsafe { <T as ZeroCopySend>::type_name() }
}

macro_rules! layout {
    ($t:ident { $($field:ident),* $(,)? }) => {{
        // SAFETY: every payload is integers, floats and arrays of them, for
        // which zero is valid.
        let zero: $t = unsafe { core::mem::zeroed() };
        Layout {
            rust: stringify!($t),
            type_name: type_name::<$t>(),
            size: size_of::<$t>(),
            align: align_of::<$t>(),
            fields: vec![$(Field {
                name: stringify!($field),
                offset: offset_of!($t, $field),
                size: core::mem::size_of_val(&zero.$field),
                ty: short_type(core::any::type_name_of_val(&zero.$field)),
            }),*],
        }
    }};
}

/// Every payload type, outer messages first, then what they contain. The
/// payloads have no padding, so a field left out of a list here shows as
/// bytes not covered (checked on the way out).
pub fn all() -> Vec<Layout> {
    let all = vec![
        layout!(PartStates { protocol_version, count, seq, stamp_ns, parts }),
        layout!(PartState {
            id,
            class,
            friction_class,
            shape,
            x,
            y,
            theta,
            vx,
            vy,
            omega,
            radius,
            vertex_count,
            reserved,
            vertices
        }),
        layout!(ForceRequest { protocol_version, count, seq, stamp_ns, deadline_ns, entries }),
        layout!(ForceEntry { part_id, force_flag, curl_flag, reserved, fx, fy, curl }),
        layout!(ExplicitSchedule { protocol_version, count, seq, stamp_ns, slots }),
        layout!(ExplicitSlot { center_index, reserved, k }),
        layout!(CoreCommand { protocol_version, command, seq, stamp_ns }),
        layout!(Schedule {
            protocol_version,
            count,
            seq,
            stamp_ns,
            cycle,
            solve_time_ns,
            parts_seq,
            parts_stamp_ns,
            request_stamp_ns,
            residual,
            condition,
            rank,
            saturated,
            at_bound,
            reserved,
            slots
        }),
        layout!(ScheduleSlot { center_index, reserved, x, y, k }),
        layout!(Rejection {
            protocol_version,
            kind,
            seq,
            message_stamp_ns,
            stamp_ns,
            parts_seq,
            parts_stamp_ns,
            reason,
            reserved,
            detail
        }),
        layout!(RigInfo {
            protocol_version,
            count,
            seq,
            stamp_ns,
            core_pid,
            cycle_slots,
            class_count,
            friction_class_count,
            slot_ticks,
            reserved,
            cycle_period_ns,
            tick_hz,
            vision_frame_hz,
            mu_m_g,
            plate_half_extent,
            k_max,
            max_part_force_n,
            max_part_force_at,
            keep_out_m,
            saturation_tolerance,
            saturation_floor,
            parts_max_age_ms,
            request_max_age_ms,
            max_future_skew_ms,
            prefix,
            centers
        }),
        layout!(RigCenter { x, y, k_bound }),
        layout!(FrameHeader {
            protocol_version,
            pixel_format,
            width,
            height,
            stride,
            reserved,
            seq,
            stamp_ns,
            exposure_ns
        }),
        layout!(Telemetry {
            protocol_version,
            state,
            seq,
            stamp_ns,
            cycle,
            plate_x,
            plate_y,
            plate_theta,
            counters,
            parts_age_ms,
            request_age_ms,
            latency,
            core_pid,
            vision_pid,
            planner_pid,
            realtime_flags,
            vision_started_ns,
            planner_started_ns,
            rejected_by_reason,
            health_source,
            health_cause,
            health_detail,
            driver
        }),
        layout!(DriverTelemetry { kind, state, faults, lost_frames, bad_frames, sync0_phase_ns }),
        layout!(CoreCounters {
            ticks,
            overruns,
            hold_events,
            schedule_swaps,
            rejected_parts,
            rejected_requests,
            rt_thread_allocations,
            driver_faults,
            driver_clamped,
            driver_rejected,
            fault_holds,
            resumes
        }),
        layout!(CoreLatencies { motor_wakeup, solver, ipc_vision_to_core, frame_to_schedule }),
        layout!(LatencyPercentiles { samples, p50_ns, p99_ns, p999_ns, max_ns }),
        layout!(FeedStatus {
            protocol_version,
            count,
            seq,
            stamp_ns,
            arrived,
            picked,
            lost,
            arrivals_blocked,
            on_plate,
            stuck,
            recent_count,
            collisions,
            time_s,
            robot_busy_s,
            stuck_after_s,
            recent,
            poses
        }),
        layout!(PickEvent {
            number,
            part_id,
            class,
            pose,
            reserved,
            time_s,
            position_error_m,
            angle_error_rad,
            on_plate_s
        }),
        layout!(PickPoseState { class, part_id, ready, reserved, x, y, theta }),
        layout!(PickCommand { protocol_version, pose, seq, stamp_ns, part_id, reserved }),
        layout!(RecipeCommand { protocol_version, path_len, seq, stamp_ns, path }),
        layout!(LineStatus {
            protocol_version,
            line_pid,
            seq,
            stamp_ns,
            opcua_sessions,
            modbus_connections,
            login_failures,
            access_denied,
            bad_arguments,
            invalid_state,
            failed_calls,
            modbus_exceptions,
            modbus_bad_frames,
            modbus_refused_connections,
            picks_sent,
            recipes_loaded,
            recipes_refused
        }),
    ];
    for l in &all {
        let covered: usize = l.fields.iter().map(|f| f.size).sum();
        assert_eq!(
            covered, l.size,
            "{}: fields cover {covered} of {} bytes (a field not listed?)",
            l.rust, l.size
        );
    }
    all
}
