//! iceoryx2 service names. Plain names: the rig's prefix is applied by the
//! caller through iceoryx2's `config.global.prefix`, so several rigs (or
//! tests) on one machine never see each other.
//!
//! An event service (wake-up of a listener) may use the same name as the
//! publish-subscribe service whose data it announces: iceoryx2 identifies a
//! service by name *and* messaging pattern.

/// [`crate::PartStates`], vision → core.
pub const PART_STATES: &str = "upm/part_states";
/// [`crate::ForceRequest`], planner → core.
pub const FORCE_REQUEST: &str = "upm/force_request";
/// [`crate::ExplicitSchedule`], planner → core.
pub const EXPLICIT_SCHEDULE: &str = "upm/explicit_schedule";
/// [`crate::CoreCommand`], operator → core (`upm resume`).
pub const CORE_COMMAND: &str = "upm/core_command";
/// [`crate::Schedule`], core → all.
pub const SCHEDULE: &str = "upm/schedule";
/// [`crate::Telemetry`], core → all.
pub const TELEMETRY: &str = "upm/telemetry";
/// [`crate::Rejection`], core → all: every refused message, whoever sent it.
pub const REJECTION: &str = "upm/rejection";
/// [`crate::RigInfo`], core → all: the rig describing itself, once at start.
pub const RIG_INFO: &str = "upm/rig_info";

/// Event: a client published to the core (see [`crate::wake_event`]).
pub const INBOX_EVENT: &str = "upm/inbox";
/// Event: vision published [`crate::PartStates`]; planners listen (the
/// pub-sub service's name with the event pattern).
pub const PART_STATES_EVENT: &str = PART_STATES;

/// Simulator ground truth ([`crate::PartStates`], world frame), core → the
/// simulated camera. Only published when the driver is a simulator.
pub const SIM_GROUND_TRUTH: &str = "upm/sim/ground_truth";

/// [`crate::FeedStatus`], core → all: a feed cell's counters, pick poses
/// and latest picks. Only published when the core runs a cell.
pub const FEED: &str = "upm/feed";

/// [`crate::PickCommand`], robot (e.g. through `upm line`) → core: a part
/// taken from a pick pose. Read only when the core runs a feed cell whose
/// robot is external.
pub const PICK: &str = "upm/pick";

/// [`crate::RecipeCommand`], line process (`upm line`) → core: load this
/// recipe (a changeover). Read only when the core runs a feed cell.
pub const RECIPE: &str = "upm/recipe";

/// [`crate::RecipeCommand`], core → all (planner, `upm line`, `upm
/// status`; history 1): the recipe its feed cell runs, at start and after
/// each changeover. Only published when the core runs a cell.
pub const RECIPE_ACTIVE: &str = "upm/recipe/active";

/// [`crate::LineStatus`], line process (`upm line`) → all, a few times a
/// second: what the line interface refused, by kind (`upm status`).
pub const LINE: &str = "upm/line";

/// Camera frames ([`crate::FrameHeader`] user header, `[u8]` pixels), frame
/// source → vision.
pub const CAMERA_FRAME: &str = "upm/camera/frame";

/// Every publish-subscribe service above, e.g. for tools that list or clean
/// up a rig.
pub const ALL: [&str; 15] = [
    PART_STATES,
    FORCE_REQUEST,
    EXPLICIT_SCHEDULE,
    CORE_COMMAND,
    SCHEDULE,
    TELEMETRY,
    REJECTION,
    RIG_INFO,
    SIM_GROUND_TRUTH,
    FEED,
    PICK,
    RECIPE,
    RECIPE_ACTIVE,
    LINE,
    CAMERA_FRAME,
];
