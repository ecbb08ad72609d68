//! Shared-memory messages of the UPM kernel (ARCHITECTURE.md §3–§4).
//!
//! Every process (core, vision, planner, tools) links this one crate, so the
//! byte layout of a message is defined exactly once. Payloads are
//! `#[repr(C)]`, [`ZeroCopySend`](iceoryx2::prelude::ZeroCopySend), have a
//! fixed capacity, no padding and only integer / float fields: any bit
//! pattern a buggy or hostile peer writes into shared memory is a valid Rust
//! value. Whether it is a *meaningful* message is decided by `validate()`,
//! which never allocates and never panics (it runs on the RT solver thread).
//!
//! Conventions shared by all messages:
//! - `protocol_version` must equal [`PROTOCOL_VERSION`];
//! - `stamp_ns` and deadlines are CLOCK_MONOTONIC nanoseconds
//!   ([`monotonic_now_ns`]); every message has a `seq` so gaps are visible;
//! - lengths are SI (m, N, rad, s) unless a field name says otherwise;
//! - `count` says how many leading entries of the fixed array are used; the
//!   slice accessors clamp it to the capacity, so a hostile count can never
//!   index out of bounds.

#![deny(unsafe_code)]

mod camera_frame;
mod capacity;
mod clock;
mod core_command;
mod core_state;
mod counted_message;
#[cfg(feature = "iceoryx2")]
pub mod discovery;
mod driver_telemetry;
mod explicit_schedule;
mod feed_status;
mod force_request;
mod header;
mod health;
mod latency_percentiles;
mod line_status;
#[cfg(feature = "iceoryx2")]
mod node_list;
pub mod part_shape;
mod part_states;
mod pick_command;
#[cfg(feature = "iceoryx2")]
pub mod ports;
mod recipe_command;
mod reject_reason;
mod rejection;
mod rig_info;
#[cfg(feature = "iceoryx2")]
pub mod rig_node;
mod schedule;
pub mod service_names;
mod telemetry;
mod validation;
#[cfg(feature = "iceoryx2")]
pub mod wake_event;
mod wire_code;
#[cfg(feature = "iceoryx2")]
pub mod wire_message;

pub use camera_frame::{FrameError, FrameHeader};
pub use capacity::{CapacityError, MAX_CENTERS, MAX_CURLS, MAX_PARTS, MAX_SLOTS};
pub use clock::monotonic_now_ns;
pub use core_command::{CoreCommand, CoreCommandError};
pub use core_state::CoreState;
pub use driver_telemetry::{DRIVER_AXES, DriverTelemetry, NO_SYNC0, bus_state, driver_kind};
pub use explicit_schedule::{ExplicitSchedule, ExplicitScheduleError, ExplicitSlot};
pub use feed_status::{
    FEED_RECENT_PICKS, FeedStatus, FeedStatusError, MAX_PICK_POSES, PickEvent, PickPoseState,
};
pub use force_request::{ForceEntry, ForceRequest, ForceRequestError};
pub use header::HeaderError;
pub use health::{DetailText, HEALTH_DETAIL_BYTES, HealthCause, HealthSource, detail_str};
pub use latency_percentiles::LatencyPercentiles;
pub use line_status::{LineStatus, LineStatusError};
pub use part_shape::{
    MAX_OUTLINE_M, MAX_SHAPE_VERTICES, MIN_OUTLINE_M, SHAPE_DISC, SHAPE_POINT, SHAPE_POLYGON, ShapeError,
};
pub use part_states::{PartState, PartStates, PartStatesError};
pub use pick_command::{PickCommand, PickCommandError};
pub use recipe_command::{RECIPE_PATH_BYTES, RecipeCommand, RecipeCommandError};
pub use reject_reason::{REJECT_REASONS, RejectReason};
pub use rejection::{RejectedKind, Rejection};
pub use rig_info::{RIG_PREFIX_BYTES, RigCenter, RigInfo, RigInfoError};
pub use schedule::{Schedule, ScheduleError, ScheduleSlot};
pub use telemetry::{CoreCounters, CoreLatencies, Telemetry, TelemetryError};
pub use validation::ValidationLimits;
#[cfg(feature = "iceoryx2")]
pub use wire_message::{WireMessage, WrongLength};

/// Version of the wire format. Bump it on any layout or meaning change; it is
/// also part of every payload's iceoryx2 `type_name`, so mismatched builds
/// fail when opening a service instead of misreading each other.
pub const PROTOCOL_VERSION: u32 = 6;
