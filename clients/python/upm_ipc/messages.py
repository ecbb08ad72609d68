"""The UPM wire messages as ctypes structures, with no iceoryx2 import (a
layout test in the Rust workspace checks them against the Rust types:
ipc-types/tests/python_layout.rs).
"""

import ctypes
import math
import time

# ipc-types/src/lib.rs and capacity.rs
PROTOCOL_VERSION = 6
MAX_PARTS = 64
MAX_CURLS = 16
MAX_SLOTS = 192
MAX_CENTERS = 192
# ipc-types/src/feed_status.rs
MAX_PICK_POSES = 16
FEED_RECENT_PICKS = 16
# ipc-types/src/recipe_command.rs
RECIPE_PATH_BYTES = 240

# ipc-types/src/part_shape.rs: PartState.shape codes
SHAPE_POINT = 0  # the paper's point part (the field at its position)
SHAPE_DISC = 1  # a disc of `radius`
SHAPE_POLYGON = 2  # a convex polygon of `vertex_count` `vertices`
MAX_SHAPE_VERTICES = 8

# How long a request stays valid (the Rust planners' REQUEST_LIFETIME_NS):
# the core holds the plate if no newer one arrives.
REQUEST_LIFETIME_NS = 300_000_000

# ipc-types/src/service_names.rs
PART_STATES = "upm/part_states"
FORCE_REQUEST = "upm/force_request"
SCHEDULE = "upm/schedule"
TELEMETRY = "upm/telemetry"
REJECTION = "upm/rejection"  # every refusal, whoever sent the message: filter
RIG_INFO = "upm/rig_info"  # the rig describing itself, once, history 1
FEED = "upm/feed"  # FeedStatus: a feed cell's counters and picks, at the camera's rate
PICK = "upm/pick"  # PickCommand: robot -> core, a part taken from a pick pose
RECIPE = "upm/recipe"  # RecipeCommand: line -> core, load this recipe (a changeover)
RECIPE_ACTIVE = "upm/recipe/active"  # RecipeCommand: core -> all, the recipe its feed cell runs, history 1
LINE = "upm/line"  # LineStatus: line -> all, what the line interface refused, by kind
CAMERA_FRAME = "upm/camera/frame"  # [u8] pixels, FrameHeader user header
INBOX_EVENT = "upm/inbox"  # event service, same name space as pub-sub
FRAME_EVENT = CAMERA_FRAME  # event service: a frame source notifies vision
PART_STATES_EVENT = PART_STATES  # event service: vision notifies planners

# ipc-types/src/ports.rs (open_pub_sub)
MAX_PUBLISHERS = 4
MAX_SUBSCRIBERS = 16
SUBSCRIBER_BUFFER = 8
HISTORY = 1
MAX_NODES = 32
# ipc-types/src/ports.rs (frame_publisher / frame_subscriber): history 0
FRAME_SUBSCRIBERS = 4
FRAME_BUFFER = 2
# ipc-types/src/wake_event.rs: max_notifiers = MAX_SUBSCRIBERS; the inbox
# and frame events 2 listeners, the part states event 16; notify() with the
# notifier's default event id, EventId 0.
INBOX_MAX_LISTENERS = 2
PART_STATES_MAX_LISTENERS = 16
INBOX_EVENT_ID = 0


def monotonic_now_ns():
    """CLOCK_MONOTONIC in ns: the time base of every stamp and deadline."""
    return time.clock_gettime_ns(time.CLOCK_MONOTONIC)


# --- payloads (ipc-types/src/*.rs); every field named, no padding ---------

class PartState(ctypes.Structure):
    """One part as seen by vision: pose (m, rad), velocity (m/s, rad/s) and
    contact outline: a point, a disc of `radius` (m), or a convex polygon of
    `vertex_count` `vertices` (m, in the part's own frame: relative to its
    position, turned by `theta` into plate axes). Fields a shape does not
    use are ignored. The core checks the outline (reject code bad_shape)."""
    _fields_ = [
        ("id", ctypes.c_uint32),
        ("class_", ctypes.c_uint32),  # `class` in Rust (a Python keyword)
        ("friction_class", ctypes.c_uint32),
        ("shape", ctypes.c_uint32),  # SHAPE_POINT, SHAPE_DISC or SHAPE_POLYGON
        ("x", ctypes.c_double), ("y", ctypes.c_double), ("theta", ctypes.c_double),
        ("vx", ctypes.c_double), ("vy", ctypes.c_double), ("omega", ctypes.c_double),
        ("radius", ctypes.c_double),
        ("vertex_count", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
        ("vertices", (ctypes.c_double * 2) * MAX_SHAPE_VERTICES),
    ]

    @staticmethod
    def type_name():
        return "upm::PartState.v6"

    @classmethod
    def point(cls, id, class_, friction_class, pose, velocity=(0.0, 0.0, 0.0)):
        """A point part (as PartState::new): pose (x, y, theta), velocity (vx, vy, omega)."""
        p = cls()
        p.id, p.class_, p.friction_class, p.shape = id, class_, friction_class, SHAPE_POINT
        p.x, p.y, p.theta = pose
        p.vx, p.vy, p.omega = velocity
        return p

    def with_disc(self, radius):
        """Make this part a disc of `radius` (m), in place; returns it. The core checks it."""
        self.shape, self.radius = SHAPE_DISC, radius
        return self

    def with_polygon(self, vertices):
        """Make this part a polygon of [(x, y), ...] in its own frame (m), in place;
        returns it. More than MAX_SHAPE_VERTICES raises ValueError; the core checks the rest."""
        if len(vertices) > MAX_SHAPE_VERTICES:
            raise ValueError(f"{len(vertices)} vertices, at most {MAX_SHAPE_VERTICES}")
        for i, (vx, vy) in enumerate(vertices):
            self.vertices[i][0], self.vertices[i][1] = vx, vy
        self.shape, self.vertex_count = SHAPE_POLYGON, len(vertices)
        return self

    def polygon(self):
        """The used vertices as (x, y) tuples (vertex_count clamped, as in Rust)."""
        return [tuple(v) for v in self.vertices[: min(self.vertex_count, MAX_SHAPE_VERTICES)]]


class PartStates(ctypes.Structure):
    """Vision -> core: every part seen in one camera frame."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("count", ctypes.c_uint32),
        ("seq", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),
        ("parts", PartState * MAX_PARTS),
    ]

    @staticmethod
    def type_name():
        return "upm::PartStates.v6"

    def __init__(self):
        super().__init__()
        self.protocol_version = PROTOCOL_VERSION

    def used(self):
        """The used entries (count clamped to the capacity, as in Rust)."""
        return self.parts[: min(self.count, MAX_PARTS)]

    def push(self, part):
        """Append a PartState; False when full."""
        if self.count >= MAX_PARTS:
            return False
        self.parts[self.count] = part
        self.count += 1
        return True


class ForceEntry(ctypes.Structure):
    """What one part should feel: force (N) and/or curl (N/m), by flag."""
    _fields_ = [
        ("part_id", ctypes.c_uint32),
        ("force_flag", ctypes.c_uint32),
        ("curl_flag", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
        ("fx", ctypes.c_double), ("fy", ctypes.c_double), ("curl", ctypes.c_double),
    ]

    @staticmethod
    def type_name():
        return "upm::ForceEntry.v6"


class ForceRequest(ctypes.Structure):
    """Planner -> core: desired forces for up to MAX_PARTS parts."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("count", ctypes.c_uint32),
        ("seq", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),
        ("deadline_ns", ctypes.c_uint64),
        ("entries", ForceEntry * MAX_PARTS),
    ]

    @staticmethod
    def type_name():
        return "upm::ForceRequest.v6"

    def __init__(self):
        super().__init__()
        self.protocol_version = PROTOCOL_VERSION

    def clear(self):
        self.count = 0

    def push_force(self, part_id, fx, fy):
        """Append a force entry (curl free); False when full."""
        if self.count >= MAX_PARTS:
            return False
        self.entries[self.count] = ForceEntry(part_id, 1, 0, 0, fx, fy, 0.0)
        self.count += 1
        return True


class ScheduleSlot(ctypes.Structure):
    _fields_ = [
        ("center_index", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
        ("x", ctypes.c_double), ("y", ctypes.c_double), ("k", ctypes.c_double),
    ]

    @staticmethod
    def type_name():
        return "upm::ScheduleSlot.v6"


class Schedule(ctypes.Structure):
    """Core -> all. `seq` and `request_stamp_ns` are those of the request it
    was solved from (match on both: history hands a restarted planner the
    last schedule, which may answer an earlier run's request of that seq).
    `residual` is one norm over force rows (N) and curl rows (N/m)."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("count", ctypes.c_uint32),
        ("seq", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),
        ("cycle", ctypes.c_uint64),
        ("solve_time_ns", ctypes.c_uint64),
        ("parts_seq", ctypes.c_uint64),
        ("parts_stamp_ns", ctypes.c_uint64),
        ("request_stamp_ns", ctypes.c_uint64),
        ("residual", ctypes.c_double),
        ("condition", ctypes.c_double),
        ("rank", ctypes.c_uint32),
        ("saturated", ctypes.c_uint32),  # 1: a bound keeps the request from being met
        ("at_bound", ctypes.c_uint32),  # centers at their bound, request met or not
        ("reserved", ctypes.c_uint32),
        ("slots", ScheduleSlot * MAX_SLOTS),
    ]

    @staticmethod
    def type_name():
        return "upm::Schedule.v6"


# Rejection.kind codes and the reject reasons (docs/protocol.md).
REJECTED_KINDS = ("part_states", "force_request", "explicit_schedule", "core_command", "pick", "recipe")
REJECT_REASONS = (
    "wrong_protocol_version", "count_exceeds_capacity", "empty", "stamp_from_future", "stale",
    "out_of_order", "duplicate", "non_finite", "off_plate", "unknown_class", "duplicate_id",
    "not_a_flag", "constrains_nothing", "too_many_curls", "deadline_before_stamp", "unknown_center",
    "k_out_of_range", "no_part_states", "unknown_part", "unsolvable", "motion_limits",
    "actuator_limits", "overflow", "receive_error", "unknown_command", "bad_shape", "bad_path",
    "bad_recipe",
)
DETAIL_BYTES = 120


class Rejection(ctypes.Structure):
    """Core -> the sender of a refused message: which, why, in one line."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("kind", ctypes.c_uint32),
        ("seq", ctypes.c_uint64),
        ("message_stamp_ns", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),
        ("parts_seq", ctypes.c_uint64),
        ("parts_stamp_ns", ctypes.c_uint64),
        ("reason", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
        ("detail", ctypes.c_uint8 * DETAIL_BYTES),
    ]

    @staticmethod
    def type_name():
        return "upm::Rejection.v6"

    def __str__(self):
        kind = REJECTED_KINDS[self.kind] if self.kind < len(REJECTED_KINDS) else "unknown"
        reason = REJECT_REASONS[self.reason] if self.reason < len(REJECT_REASONS) else "unknown"
        text = bytes(self.detail).split(b"\0", 1)[0].decode("utf-8", "replace")
        return f"{kind} seq {self.seq} rejected: {reason} ({text})"


RIG_PREFIX_BYTES = 64


class RigCenter(ctypes.Structure):
    """A rotation center (m, plate axes) and the bound on |k| the core solves under there."""
    _fields_ = [("x", ctypes.c_double), ("y", ctypes.c_double), ("k_bound", ctypes.c_double)]

    @staticmethod
    def type_name():
        return "upm::RigCenter.v6"


class RigInfo(ctypes.Structure):
    """Core -> all, once at start (history 1): the rig describing itself."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("count", ctypes.c_uint32),  # used entries of centers
        ("seq", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),
        ("core_pid", ctypes.c_uint32),
        ("cycle_slots", ctypes.c_uint32),  # 0: one slot per center; N: sparse cycles of N slots
        ("class_count", ctypes.c_uint32),  # codes below it; 0xFFFFFFFF: any
        ("friction_class_count", ctypes.c_uint32),
        ("slot_ticks", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
        ("cycle_period_ns", ctypes.c_uint64),
        ("tick_hz", ctypes.c_double),
        ("vision_frame_hz", ctypes.c_double),  # PartStates rate; 0: not known
        ("mu_m_g", ctypes.c_double),  # N
        ("plate_half_extent", ctypes.c_double * 2),  # m
        ("k_max", ctypes.c_double),
        ("max_part_force_n", ctypes.c_double),  # anywhere on the plate; max_force() for a place
        ("max_part_force_at", ctypes.c_double * 2),
        ("keep_out_m", ctypes.c_double),
        ("saturation_tolerance", ctypes.c_double),
        ("saturation_floor", ctypes.c_double),
        ("parts_max_age_ms", ctypes.c_double),
        ("request_max_age_ms", ctypes.c_double),
        ("max_future_skew_ms", ctypes.c_double),
        ("prefix", ctypes.c_uint8 * RIG_PREFIX_BYTES),
        ("centers", RigCenter * MAX_CENTERS),
    ]

    @staticmethod
    def type_name():
        return "upm::RigInfo.v6"

    def used(self):
        """The used centers (count clamped to the capacity, as in Rust)."""
        return self.centers[: min(self.count, MAX_CENTERS)]

    def prefix_str(self):
        return bytes(self.prefix).split(b"\0", 1)[0].decode("utf-8", "replace")


def max_force(info, x, y, ux, uy):
    """The largest force (N) one point part at (x, y) can be given along the
    direction (ux, uy), curl free, on the rig `info` (a RigInfo) describes:
    where the ray along it leaves the set of forces one cycle can give
    (docs/protocol.md, "How hard a part can be pushed"). Several parts
    share a cycle: together they get less."""
    norm = math.hypot(ux, uy)
    if not norm > 0.0:
        raise ValueError("the direction (ux, uy) must not be zero")
    d = (ux / norm, uy / norm)
    sparse = info.cycle_slots > 0
    near = info.keep_out_m if sparse else 1e-9
    tangents = []  # (t_j, u_j) of the centers that may push the part
    for c in info.used():
        rx, ry = x - c.x, y - c.y
        r = math.hypot(rx, ry)
        if r >= near:
            tangents.append(((-ry / r, rx / r), c.k_bound))
    if sparse:
        # mu_m_g * conv{+-u_j t_j}: the farthest crossing with a chord.
        q = [p for (t, u) in tangents for p in ((u * t[0], u * t[1]), (-u * t[0], -u * t[1]))]
        best = 0.0
        for a, qa in enumerate(q):
            n = math.hypot(*qa)
            if abs(d[0] * qa[1] - d[1] * qa[0]) <= 1e-12 * n and d[0] * qa[0] + d[1] * qa[1] > 0.0:
                best = max(best, n)
            for qb in q[a + 1:]:
                ex, ey = qb[0] - qa[0], qb[1] - qa[1]
                den = d[0] * ey - d[1] * ex
                if den == 0.0:
                    continue
                s = (qa[0] * qb[1] - qa[1] * qb[0]) / den
                lam = -(d[0] * qa[1] - d[1] * qa[0]) / den
                if 0.0 <= lam <= 1.0 and s > best:
                    best = s
        return info.mu_m_g * best
    # Paper's cycle: a zonotope whose facet normals are the radial e_k.
    best = math.inf
    for tk, _ in tangents:
        e = (tk[1], -tk[0])
        across = abs(e[0] * d[0] + e[1] * d[1])
        if across > 1e-12:
            h = sum(u * abs(e[0] * t[0] + e[1] * t[1]) for t, u in tangents)
            best = min(best, h / across)
    if best == math.inf:  # every tangent along d
        best = sum(u * abs(d[0] * t[0] + d[1] * t[1]) for t, u in tangents)
    return info.mu_m_g / max(len(info.used()), 1) * best


class FrameHeader(ctypes.Structure):
    """Frame source -> vision: the user header of one camera frame; the
    payload is stride * height bytes of mono8 pixels."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("pixel_format", ctypes.c_uint32),
        ("width", ctypes.c_uint32),
        ("height", ctypes.c_uint32),
        ("stride", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
        ("seq", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),
        ("exposure_ns", ctypes.c_uint64),
    ]

    @staticmethod
    def type_name():
        return "upm::FrameHeader.v6"


class PickPoseState(ctypes.Structure):
    """One pick pose of the recipe (m, m, rad, plate axes), and whether a
    part waits there: `part_id` (0: none), `ready` 1 when the robot may take it."""
    _fields_ = [
        ("class_", ctypes.c_uint32),  # `class` in Rust (a Python keyword)
        ("part_id", ctypes.c_uint32),
        ("ready", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
        ("x", ctypes.c_double), ("y", ctypes.c_double), ("theta", ctypes.c_double),
    ]

    @staticmethod
    def type_name():
        return "upm::PickPoseState.v6"


class PickEvent(ctypes.Structure):
    """One pick, at the instant the robot closed on the part; `number` is 1
    for the cell's first pick, then one more for each."""
    _fields_ = [
        ("number", ctypes.c_uint64),
        ("part_id", ctypes.c_uint32),
        ("class_", ctypes.c_uint32),  # `class` in Rust (a Python keyword)
        ("pose", ctypes.c_uint32),  # index into FeedStatus.poses
        ("reserved", ctypes.c_uint32),
        ("time_s", ctypes.c_double),  # s since the cell started
        ("position_error_m", ctypes.c_double),
        ("angle_error_rad", ctypes.c_double),
        ("on_plate_s", ctypes.c_double),  # from the part's arrival to its pick
    ]

    @staticmethod
    def type_name():
        return "upm::PickEvent.v6"


class FeedStatus(ctypes.Structure):
    """Core -> all on FEED, at the camera's rate while it runs a feed cell:
    its counters, its pick poses (`count` used) and its latest picks
    (`recent_count` used, oldest first)."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("count", ctypes.c_uint32),  # used entries of poses
        ("seq", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),
        ("arrived", ctypes.c_uint64),  # since the cell started
        ("picked", ctypes.c_uint64),
        ("lost", ctypes.c_uint64),
        ("arrivals_blocked", ctypes.c_uint64),
        ("on_plate", ctypes.c_uint32),  # parts on the plate now
        ("stuck", ctypes.c_uint32),  # of them, there longer than stuck_after_s
        ("recent_count", ctypes.c_uint32),
        ("collisions", ctypes.c_uint32),  # part-part impacts (the simulator counts them; else 0)
        ("time_s", ctypes.c_double),  # the cell's clock
        ("robot_busy_s", ctypes.c_double),
        ("stuck_after_s", ctypes.c_double),
        ("recent", PickEvent * FEED_RECENT_PICKS),
        ("poses", PickPoseState * MAX_PICK_POSES),
    ]

    @staticmethod
    def type_name():
        return "upm::FeedStatus.v6"

    def used(self):
        """The used pick poses (count clamped to the capacity, as in Rust)."""
        return self.poses[: min(self.count, MAX_PICK_POSES)]

    def picks(self, after=0):
        """The latest picks, oldest first (recent_count clamped, as in Rust),
        those numbered above `after`: pass the last number seen to keep every
        pick, as long as fewer than FEED_RECENT_PICKS happen between two reads."""
        return [p for p in self.recent[: min(self.recent_count, FEED_RECENT_PICKS)] if p.number > after]


class PickCommand(ctypes.Structure):
    """Robot -> core on PICK: "I took the part `part_id` from pick pose
    `pose`" (an index into FeedStatus.poses, below MAX_PICK_POSES; part_id
    as that pose showed it while ready, not 0). Read by a core whose feed
    cell's robot is external; refused ones come back on REJECTION, kind "pick"."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("pose", ctypes.c_uint32),
        ("seq", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),  # CLOCK_MONOTONIC ns when sent
        ("part_id", ctypes.c_uint32),
        ("reserved", ctypes.c_uint32),
    ]

    @staticmethod
    def type_name():
        return "upm::PickCommand.v6"

    def __init__(self, pose=0, part_id=0, seq=0, stamp_ns=0):
        """As PickCommand::new: the protocol version set, reserved 0."""
        super().__init__(PROTOCOL_VERSION, pose, seq, stamp_ns, part_id, 0)


class RecipeCommand(ctypes.Structure):
    """Line process -> core on RECIPE: "load the recipe at `path`" (a
    changeover); the core announces the recipe its feed cell runs on
    RECIPE_ACTIVE (history 1), which planners follow. `path` is the recipe
    file's absolute path, UTF-8, `path_len` bytes used (at most
    RECIPE_PATH_BYTES), the rest 0. Refused ones come back on REJECTION,
    kind "recipe"."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("path_len", ctypes.c_uint32),  # used bytes of path
        ("seq", ctypes.c_uint64),
        ("stamp_ns", ctypes.c_uint64),  # CLOCK_MONOTONIC ns when sent
        ("path", ctypes.c_uint8 * RECIPE_PATH_BYTES),
    ]

    @staticmethod
    def type_name():
        return "upm::RecipeCommand.v6"

    def __init__(self, path=None, seq=0, stamp_ns=0):
        """As RecipeCommand::new: the protocol version set, `path` copied
        in; ValueError if it is longer than RECIPE_PATH_BYTES (as UTF-8) or
        not absolute. Without a path (as copy_out makes one) it is empty."""
        if path is None:
            super().__init__(PROTOCOL_VERSION, 0, seq, stamp_ns)
            return
        raw = path.encode("utf-8")
        if len(raw) > RECIPE_PATH_BYTES:
            raise ValueError(f"recipe_command.path_len {len(raw)} exceeds the capacity {RECIPE_PATH_BYTES}")
        if not raw.startswith(b"/"):
            raise ValueError("recipe_command.path is not absolute: it must start with '/'")
        super().__init__(PROTOCOL_VERSION, len(raw), seq, stamp_ns)
        ctypes.memmove(self.path, raw, len(raw))

    def path_str(self):
        """The used bytes of `path` as text (as RecipeCommand::path); ValueError
        if `path_len` exceeds the capacity or the bytes are not UTF-8."""
        if self.path_len > RECIPE_PATH_BYTES:
            raise ValueError(f"recipe_command.path_len {self.path_len} exceeds the capacity {RECIPE_PATH_BYTES}")
        try:
            return bytes(self.path[: self.path_len]).decode("utf-8")
        except UnicodeDecodeError:
            raise ValueError("recipe_command.path is not UTF-8") from None


# LineStatus's refusal counters, in field order (LineStatus::refusals).
LINE_REFUSALS = (
    "login_failures", "access_denied", "bad_arguments", "invalid_state", "failed_calls",
    "modbus_exceptions", "modbus_bad_frames", "modbus_refused_connections",
)


class LineStatus(ctypes.Structure):
    """Line process -> all on LINE, a few times a second: the line
    interface's open OPC UA sessions and Modbus connections, what it
    refused since it started, by kind, and what it passed on to the rig."""
    _fields_ = [
        ("protocol_version", ctypes.c_uint32),
        ("line_pid", ctypes.c_uint32),
        ("seq", ctypes.c_uint64),  # one more for each status
        ("stamp_ns", ctypes.c_uint64),
        ("opcua_sessions", ctypes.c_uint32),  # open now
        ("modbus_connections", ctypes.c_uint32),  # open now
        ("login_failures", ctypes.c_uint64),  # OPC UA logins: unknown user or wrong password
        ("access_denied", ctypes.c_uint64),  # calls or writes refused for want of a user
        ("bad_arguments", ctypes.c_uint64),  # calls with arguments of wrong type or number
        ("invalid_state", ctypes.c_uint64),  # Picked on a pose with no part ready
        ("failed_calls", ctypes.c_uint64),  # calls the rig could not carry out
        ("modbus_exceptions", ctypes.c_uint64),  # Modbus requests answered with an exception
        ("modbus_bad_frames", ctypes.c_uint64),  # Modbus connections closed on a malformed frame
        ("modbus_refused_connections", ctypes.c_uint64),  # beyond the limit
        ("picks_sent", ctypes.c_uint64),  # PickCommands passed on to the rig
        ("recipes_loaded", ctypes.c_uint64),
        ("recipes_refused", ctypes.c_uint64),
    ]

    @staticmethod
    def type_name():
        return "upm::LineStatus.v6"

    def __init__(self):
        """As LineStatus::new: the protocol version set, the rest 0."""
        super().__init__()
        self.protocol_version = PROTOCOL_VERSION

    def refusals(self):
        """[(name, count)] of the eight refusal counters, in field order."""
        return [(name, getattr(self, name)) for name in LINE_REFUSALS]

    def total_refusals(self):
        """Every refusal since the line started (saturating at 2**64 - 1, as in Rust)."""
        return min(sum(n for _, n in self.refusals()), 2**64 - 1)


# The Rust `const _: () = assert!(size_of::<..>() == ..)` lines.
assert ctypes.sizeof(PartState) == 4 * 4 + 7 * 8 + 2 * 4 + MAX_SHAPE_VERTICES * 16
assert ctypes.sizeof(PartStates) == 4 + 4 + 8 + 8 + MAX_PARTS * ctypes.sizeof(PartState)
assert ctypes.sizeof(ForceEntry) == 4 * 4 + 3 * 8
assert ctypes.sizeof(ForceRequest) == 4 + 4 + 3 * 8 + MAX_PARTS * ctypes.sizeof(ForceEntry)
assert ctypes.sizeof(ScheduleSlot) == 4 + 4 + 3 * 8
assert ctypes.sizeof(Schedule) == 4 + 4 + 7 * 8 + 2 * 8 + 4 * 4 + MAX_SLOTS * ctypes.sizeof(ScheduleSlot)
assert ctypes.sizeof(RigCenter) == 3 * 8
assert ctypes.sizeof(RigInfo) == 24 + 6 * 4 + 8 + 15 * 8 + RIG_PREFIX_BYTES + MAX_CENTERS * 24
assert ctypes.sizeof(Rejection) == 4 + 4 + 5 * 8 + 4 + 4 + DETAIL_BYTES
assert ctypes.sizeof(PickPoseState) == 4 * 4 + 3 * 8
assert ctypes.sizeof(PickEvent) == 8 + 4 * 4 + 4 * 8
assert ctypes.sizeof(FeedStatus) == (
    4 + 4 + 2 * 8 + 4 * 8 + 4 * 4 + 3 * 8
    + FEED_RECENT_PICKS * ctypes.sizeof(PickEvent) + MAX_PICK_POSES * ctypes.sizeof(PickPoseState)
)
assert ctypes.sizeof(PickCommand) == 4 + 4 + 8 + 8 + 4 + 4
assert ctypes.sizeof(RecipeCommand) == 4 + 4 + 8 + 8 + RECIPE_PATH_BYTES
assert ctypes.sizeof(LineStatus) == 4 + 4 + 8 + 8 + 4 + 4 + 11 * 8
