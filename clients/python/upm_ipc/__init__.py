"""Python client of a UPM rig over iceoryx2 0.10 shared memory
(`iox2.ServiceType.Ipc`).

Mirrors the Rust crate `ipc-types`: the `#[repr(C)]` payloads as
`ctypes.Structure`s with the same `type_name`, and the services opened with
the settings of `ipc_types::ports::open_pub_sub` and
`ipc_types::wake_event`. iceoryx2 refuses to open a service whose payload
type name, size or alignment differ, or whose creator chose a smaller
capacity than the opener asks; and whoever opens first creates the service
with its own values, so a client that asked for less would keep the core
from starting. Hence the rig's exact values here.

    rig = upm_ipc.connect("upm_")
    info = rig.rig_info()                  # RigInfo: mu_m_g, plate, centers, limits, ...
    while rig.wait_part_states(0.1) is not None:   # None: SIGINT/SIGTERM
        states = rig.newest_part_states()  # PartStates or None
        rig.send_request(req)              # publish + wake the core
"""

import ctypes
import os
import stat

import iceoryx2 as iox2

from .messages import (  # noqa: F401 (re-exported: the messages are the API)
    FEED, FEED_RECENT_PICKS, FORCE_REQUEST, FRAME_EVENT, HISTORY, INBOX_EVENT, INBOX_EVENT_ID,
    INBOX_MAX_LISTENERS, LINE, LINE_REFUSALS, MAX_CENTERS, MAX_CURLS, MAX_NODES, MAX_PARTS, MAX_PICK_POSES,
    MAX_PUBLISHERS, MAX_SHAPE_VERTICES, MAX_SLOTS, MAX_SUBSCRIBERS, PART_STATES, PART_STATES_EVENT,
    PART_STATES_MAX_LISTENERS, PICK, PROTOCOL_VERSION, RECIPE, RECIPE_ACTIVE, RECIPE_PATH_BYTES,
    REJECTED_KINDS, REJECTION, REQUEST_LIFETIME_NS, RIG_INFO, SCHEDULE, SHAPE_DISC, SHAPE_POINT, SHAPE_POLYGON,
    SUBSCRIBER_BUFFER, TELEMETRY,
    FeedStatus, ForceEntry, ForceRequest, LineStatus, PartState, PartStates, PickCommand, PickEvent,
    PickPoseState, RecipeCommand, Rejection, RigCenter, RigInfo, Schedule, ScheduleSlot,
    max_force, monotonic_now_ns,
)

__all__ = [
    "PROTOCOL_VERSION", "MAX_PARTS", "MAX_CURLS", "MAX_SLOTS", "MAX_CENTERS", "REQUEST_LIFETIME_NS",
    "SHAPE_POINT", "SHAPE_DISC", "SHAPE_POLYGON", "MAX_SHAPE_VERTICES", "MAX_PICK_POSES", "FEED_RECENT_PICKS",
    "RECIPE_PATH_BYTES", "LINE_REFUSALS",
    "PART_STATES", "FORCE_REQUEST", "SCHEDULE", "TELEMETRY", "REJECTION", "RIG_INFO", "FEED", "PICK",
    "RECIPE", "RECIPE_ACTIVE", "LINE", "INBOX_EVENT",
    "FRAME_EVENT", "PART_STATES_EVENT",
    "PartState", "PartStates", "ForceEntry", "ForceRequest", "ScheduleSlot", "Schedule", "Rejection",
    "RigCenter", "RigInfo", "PickPoseState", "PickEvent", "FeedStatus", "PickCommand", "RecipeCommand",
    "LineStatus", "max_force",
    "monotonic_now_ns", "config_with_prefix", "open_pub_sub", "open_inbox_event", "open_wake_event", "copy_out",
    "Rig", "connect",
]

# Longest uninterrupted listener wait: SIGINT/SIGTERM are seen between two.
_WAIT_SLICE_S = 0.05

# --- services --------------------------------------------------------------

def config_with_prefix(prefix):
    """iceoryx2 config isolated to one rig by its prefix (ports.rs).

    `global_cfg` returns a live reference: assigning its `prefix` changes
    the config itself."""
    config = iox2.config.default()
    config.global_cfg.prefix = iox2.FileName.new(prefix)
    return config


def open_pub_sub(node, name, payload_type):
    """Open or create `name` with the rig's settings (ports.rs)."""
    return (
        node.service_builder(iox2.ServiceName.new(name))
        .publish_subscribe(payload_type)
        .max_publishers(MAX_PUBLISHERS)
        .max_subscribers(MAX_SUBSCRIBERS)
        .subscriber_max_buffer_size(SUBSCRIBER_BUFFER)
        .history_size(HISTORY)
        .enable_safe_overflow(True)
        .max_nodes(MAX_NODES)
        .open_or_create()
    )


def open_inbox_event(node):
    """The core's wake-up event, with the settings of wake_event.rs."""
    return open_wake_event(node, INBOX_EVENT)


def open_wake_event(node, service):
    """A wake-up event (INBOX_EVENT, FRAME_EVENT or PART_STATES_EVENT), as
    wake_event.rs opens it; the rest is iceoryx2's defaults."""
    listeners = PART_STATES_MAX_LISTENERS if service == PART_STATES_EVENT else INBOX_MAX_LISTENERS
    return (
        node.service_builder(iox2.ServiceName.new(service))
        .event()
        .max_notifiers(MAX_SUBSCRIBERS)
        .max_listeners(listeners)
        .max_nodes(MAX_NODES)
        .open_or_create()
    )


def _restrict_to_owner(prefix, shm_dir="/dev/shm"):
    """As rig_node.rs: iceoryx2 creates the prefix's node-counter segment
    world-writable; tighten what this user owns to owner-only."""
    me = os.geteuid()
    try:
        names = os.listdir(shm_dir)
    except OSError:
        return
    for name in names:
        if not name.startswith(prefix):
            continue
        path = os.path.join(shm_dir, name)
        try:
            st = os.stat(path)
            if st.st_uid == me and st.st_mode & 0o077:
                os.chmod(path, stat.S_IMODE(st.st_mode) & 0o700)
        except OSError:
            pass  # vanished meanwhile


def copy_out(sample, payload_type):
    """Copy a received sample out of shared memory (the publisher may reuse
    it) and release the sample at once."""
    value = payload_type()
    ctypes.memmove(ctypes.byref(value), sample.payload_ptr, ctypes.sizeof(payload_type))
    sample.delete()
    return value


class Rig:
    """A client's ports on one rig: RigInfo and PartStates in (with vision's
    wake-up), ForceRequest out, Rejections (and Schedules) back."""

    def __init__(self, prefix, name="upm-planner-py", schedules=False):
        self.prefix = prefix
        self.node = (
            iox2.NodeBuilder.new()
            .config(config_with_prefix(prefix))
            .name(iox2.NodeName.new(name))
            .signal_handling_mode(iox2.SignalHandlingMode.HandleTerminationRequests)
            .create(iox2.ServiceType.Ipc)
        )
        _restrict_to_owner(prefix)
        self._parts = open_pub_sub(self.node, PART_STATES, PartStates).subscriber_builder().create()
        self._requests = open_pub_sub(self.node, FORCE_REQUEST, ForceRequest).publisher_builder().create()
        self._wake = (
            open_inbox_event(self.node)
            .notifier_builder()
            .default_event_id(iox2.EventId.new(INBOX_EVENT_ID))
            .create()
        )
        # Every refusal the core makes, whoever sent the message: rejections() keeps ours.
        self._rejections = open_pub_sub(self.node, REJECTION, Rejection).subscriber_builder().create()
        self._schedules = None
        if schedules:
            self._schedules = open_pub_sub(self.node, SCHEDULE, Schedule).subscriber_builder().create()
        # Vision notifies it after each PartStates (up to 16 listeners).
        self._woken = open_wake_event(self.node, PART_STATES_EVENT).listener_builder().create()
        self._rig_info = open_pub_sub(self.node, RIG_INFO, RigInfo).subscriber_builder().create()
        self._info = None
        self._sent = {}  # (kind, seq) -> stamp_ns of what this client sent
        self.notify_failures = 0
        # True once SIGINT or SIGTERM arrived: time to exit.
        self.stop_requested = False
        self._stopping()  # installs iceoryx2's signal handler now

    @staticmethod
    def _received(subscriber):
        """Every sample waiting on `subscriber`, oldest first (each must be
        copied out or deleted by the caller)."""
        while (sample := subscriber.receive()) is not None:
            yield sample

    def newest_part_states(self):
        """Drain the subscriber; the newest PartStates or None."""
        newest = None
        for sample in self._received(self._parts):
            newest = copy_out(sample, PartStates)
        return newest

    def receive_schedules(self):
        """All Schedules received since the last call, oldest first
        (only with connect(..., schedules=True))."""
        return [copy_out(s, Schedule) for s in self._received(self._schedules)]

    def rejections(self, mine=False):
        """Rejections received since the last call, oldest first; print one
        to see why (`force_request seq 7 rejected: stale (...)`).
        `upm/rejection` carries every refusal the core makes, vision's too.
        `mine=True` keeps those of requests this Rig sent: same kind, `seq`
        and `message_stamp_ns`."""
        got = [copy_out(s, Rejection) for s in self._received(self._rejections)]
        if not mine:
            return got
        kind = REJECTED_KINDS.index("force_request")
        return [r for r in got if r.kind == kind and self._sent.get(r.seq) == r.message_stamp_ns]

    def rig_info(self, timeout=1.0):
        """The rig's description (RigInfo), or None if no core published one
        within `timeout` seconds. The core publishes it once at start with a
        history of 1: it arrives a few ms after subscribing; kept after."""
        end = monotonic_now_ns() + int(timeout * 1e9)
        while self._info is None:
            for sample in self._received(self._rig_info):
                self._info = copy_out(sample, RigInfo)
            if self._info is not None or monotonic_now_ns() >= end or not self.wait(0.002):
                break
        return self._info

    def wait_part_states(self, timeout):
        """Sleep until vision announces new PartStates or `timeout` seconds
        pass: True when announced (read them with newest_part_states()),
        False on timeout, None once SIGINT/SIGTERM arrived (time to exit;
        also `stop_requested`). Vision publishes at RigInfo.vision_frame_hz."""
        end = monotonic_now_ns() + int(timeout * 1e9)
        while True:
            if self._stopping():
                return None
            left = (end - monotonic_now_ns()) / 1e9
            if left <= 0:
                return False
            try:
                if self._woken.timed_wait(iox2.Duration.from_secs_f64(min(left, _WAIT_SLICE_S))):
                    return True
            except iox2.ListenerWaitError:
                pass  # a signal: SIGINT/SIGTERM is seen at the loop's top

    def send_request(self, req):
        """Publish `req` (seq, stamp_ns, deadline_ns already filled), then
        wake the core's receiver. A lost wake-up costs one receiver poll."""
        sample = self._requests.loan_uninit()
        ctypes.memmove(sample.payload_ptr, ctypes.byref(req), ctypes.sizeof(ForceRequest))
        sample.assume_init().send()
        self._sent[req.seq] = req.stamp_ns
        if len(self._sent) > 4096:  # only recent ones can still be refused
            for seq in sorted(self._sent)[:2048]:
                del self._sent[seq]
        try:
            self._wake.notify()
        except iox2.NotifierNotifyError:
            self.notify_failures += 1

    def _stopping(self):
        """True once SIGINT/SIGTERM arrived (iceoryx2 reports it once: kept)."""
        if not self.stop_requested:
            try:
                self.node.wait(iox2.Duration.from_nanos(0))
            except iox2.NodeWaitFailure:
                self.stop_requested = True
        return self.stop_requested

    def wait(self, seconds):
        """Sleep via the node. False on SIGINT/SIGTERM (time to exit)."""
        if self.stop_requested:
            return False
        try:
            self.node.wait(iox2.Duration.from_secs_f64(seconds))
            return True
        except iox2.NodeWaitFailure:
            self.stop_requested = True
            return False

    def close(self):
        """Release the ports and the node (else the garbage collector does)."""
        ports = (self._wake, self._requests, self._parts, self._rejections, self._schedules, self._woken,
                 self._rig_info)
        for port in ports:
            if port is not None:
                port.delete()
        self.node = None


def connect(prefix, name="upm-planner-py", schedules=False):
    """A client on the rig with iceoryx2 prefix `prefix` (e.g. "upm_")."""
    return Rig(prefix, name=name, schedules=schedules)
