"""A planner as a stranger writes it: from docs/protocol.md and iceoryx2's
own Python package, nothing else. The message layouts, service names and
settings are read from the doc's tables when it starts (so the doc, not
clients/python, is what is tested); it checks every layout it builds
against the doc's offsets and sizes, then gathers the parts towards the
plate's centre until SIGINT, and prints what it sent, what was answered
and what was refused.

    UPM_PREFIX=… python3 planner.py DOCS/protocol.md PIDFILE
"""
import ctypes
import math
import os
import re
import sys
import time

import iceoryx2 as iox2

SCALARS = {
    "u8": ctypes.c_uint8, "u16": ctypes.c_uint16, "u32": ctypes.c_uint32, "u64": ctypes.c_uint64,
    "i8": ctypes.c_int8, "i16": ctypes.c_int16, "i32": ctypes.c_int32, "i64": ctypes.c_int64,
    "f32": ctypes.c_float, "f64": ctypes.c_double,
}


def cells(line):
    return [c.strip().strip("`") for c in line.strip().strip("|").split("|")]


def table_after(lines, start):
    """Rows of the first table at or after line `start` (header skipped)."""
    i = start
    while i < len(lines) and not lines[i].startswith("|"):
        i += 1
    rows = []
    for line in lines[i + 2:]:
        if not line.startswith("|"):
            break
        rows.append(cells(line))
    return rows


def table_with_header(lines, first_cell):
    """Rows of the table whose header's first cell is `first_cell`."""
    for i, line in enumerate(lines):
        if line.startswith("|") and cells(line)[0] == first_cell:
            return table_after(lines, i)
    raise SystemExit(f"planner.py: docs/protocol.md has no table headed {first_cell!r}")


class Doc:
    """What docs/protocol.md says: payloads, services, settings."""

    HEADING = re.compile(r"^### `(upm::\w+\.v\d+)` \((\w+), (\d+) bytes, align (\d+)\)")

    def __init__(self, path):
        self.lines = open(path, encoding="utf-8").read().splitlines()
        self.tables = {}  # Rust name -> (type name, size, [(field, offset, size, type)])
        for i, line in enumerate(self.lines):
            m = self.HEADING.match(line)
            if m:
                rows = [(r[0], int(r[1]), int(r[2]), r[3]) for r in table_after(self.lines, i + 1)]
                self.tables[m.group(2)] = (m.group(1), int(m.group(3)), rows)
        self.types = {}

    def ctype(self, spec):
        """`u32`, `[f64; 2]`, `[[f64; 2]; 8]`, `PartState`, `[PartState; 64]`."""
        spec = spec.strip()
        m = re.fullmatch(r"\[(.*); (\d+)\]", spec)
        if m:
            return self.ctype(m.group(1)) * int(m.group(2))
        if spec in SCALARS:
            return SCALARS[spec]
        return self.struct(spec)

    def struct(self, rust):
        """The ctypes structure the doc's table for `rust` describes,
        checked against the documented offsets and size."""
        if rust in self.types:
            return self.types[rust]
        if rust not in self.tables:
            raise SystemExit(f"planner.py: docs/protocol.md has no payload table for {rust}")
        name, size, rows = self.tables[rust]
        fields = [(field, self.ctype(ty)) for field, _, _, ty in rows]
        cls = type(rust, (ctypes.Structure,), {"_fields_": fields, "type_name": staticmethod(lambda n=name: n)})
        for field, offset, fsize, ty in rows:
            got = getattr(cls, field)
            if (got.offset, got.size) != (offset, fsize):
                raise SystemExit(f"planner.py: {rust}.{field} ({ty}) lands at {got.offset}+{got.size}, "
                                 f"the doc says {offset}+{fsize}")
        if ctypes.sizeof(cls) != size:
            raise SystemExit(f"planner.py: {rust} is {ctypes.sizeof(cls)} bytes, the doc says {size}")
        self.types[rust] = cls
        return cls

    def service(self, rust):
        """The publish-subscribe service carrying `rust`."""
        name = self.tables[rust][0]
        for row in table_with_header(self.lines, "service"):
            if row[1] == name:
                return row[0]
        raise SystemExit(f"planner.py: no service carries {name}")

    def settings(self, first_cell):
        return {row[0]: row[1] for row in table_with_header(self.lines, first_cell)}

    def event_settings(self, service):
        """The column of the events table headed `service`."""
        for i, line in enumerate(self.lines):
            head = cells(line) if line.startswith("|") else []
            if head and head[0] == "event setting":
                column = head.index(service)
                return {row[0]: row[column] for row in table_after(self.lines, i)}
        raise SystemExit("planner.py: docs/protocol.md has no events table")


def apply(builder, settings):
    """Each numeric or boolean setting the doc lists, by its builder method
    (the doc's names are iceoryx2's)."""
    for key, value in settings.items():
        method = getattr(builder, key, None)
        if method is None:
            continue
        if value in ("true", "false"):
            builder = method(value == "true")
        elif re.fullmatch(r"\d+", value):
            builder = method(int(value))
    return builder


def copy_out(sample, cls):
    value = cls()
    ctypes.memmove(ctypes.byref(value), sample.payload_ptr, ctypes.sizeof(cls))
    sample.delete()
    return value


def now_ns():
    return time.clock_gettime_ns(time.CLOCK_MONOTONIC)


def main():
    doc = Doc(sys.argv[1])
    with open(sys.argv[2], "w") as f:
        f.write(str(os.getpid()))
    version = int(re.search(r"`PROTOCOL_VERSION` = (\d+)", "\n".join(doc.lines)).group(1))
    PartStates, ForceRequest = doc.struct("PartStates"), doc.struct("ForceRequest")
    Schedule, Rejection, RigInfo = doc.struct("Schedule"), doc.struct("Rejection"), doc.struct("RigInfo")

    config = iox2.config.default()
    config.global_cfg.prefix = iox2.FileName.new(os.environ["UPM_PREFIX"])
    node = (iox2.NodeBuilder.new().config(config).name(iox2.NodeName.new("upm-planner-stranger"))
            .signal_handling_mode(iox2.SignalHandlingMode.HandleTerminationRequests)
            .create(iox2.ServiceType.Ipc))
    pubsub = doc.settings("setting")

    def open_service(rust):
        builder = node.service_builder(iox2.ServiceName.new(doc.service(rust))).publish_subscribe(doc.struct(rust))
        return apply(builder, pubsub).open_or_create()

    def open_event(name):
        builder = node.service_builder(iox2.ServiceName.new(name)).event()
        return apply(builder, doc.event_settings(name)).open_or_create()

    parts = open_service("PartStates").subscriber_builder().create()
    requests = open_service("ForceRequest").publisher_builder().create()
    schedules = open_service("Schedule").subscriber_builder().create()
    rejections = open_service("Rejection").subscriber_builder().create()
    rig_info = open_service("RigInfo").subscriber_builder().create()
    inbox = open_event("upm/inbox").notifier_builder().create()
    wake = open_event(doc.service("PartStates")).listener_builder().create()

    info = None
    while info is None:
        sample = rig_info.receive()
        if sample is not None:
            info = copy_out(sample, RigInfo)
        elif not wait(node, 0.01):
            return
    half_x, half_y = info.plate_half_extent
    gain_force = 0.3 * info.max_part_force_n  # well inside what a part can get
    prefix = bytes(info.prefix).rstrip(b"\0").decode()
    print(f"planner.py: rig {prefix} mu_m_g {info.mu_m_g} N, "
          f"plate ±{half_x}×±{half_y} m, {info.count} centers, max force {info.max_part_force_n:.4f} N, "
          f"vision {info.vision_frame_hz} Hz", flush=True)

    sent = {}  # seq -> stamp
    answered, refused, seq = set(), [], 0
    req = ForceRequest()
    while True:
        # Sleep until vision publishes (or 100 ms), then take the newest.
        try:
            woke = wake.timed_wait(iox2.Duration.from_millis(100))
        except iox2.ListenerWaitError:
            break
        del woke
        newest = None
        while (sample := parts.receive()) is not None:
            newest = copy_out(sample, PartStates)
        for s in drain(schedules, Schedule):
            if sent.get(s.seq) == s.request_stamp_ns:  # ours, not an older run's
                answered.add(s.seq)
        for r in drain(rejections, Rejection):
            # Broadcast: ours are kind 1 (ForceRequest) with our seq and stamp.
            if r.kind == 1 and sent.get(r.seq) == r.message_stamp_ns:
                refused.append(bytes(r.detail).rstrip(b"\0").decode(errors="replace"))
        if newest is not None and newest.count > 0:
            req.count = 0
            for p in newest.parts[:min(newest.count, len(newest.parts))]:
                d = max(math.hypot(p.x, p.y), 1e-9)
                scale = gain_force * min(d / 0.1, 1.0) / d
                e = req.entries[req.count]
                e.part_id, e.force_flag, e.curl_flag, e.reserved = p.id, 1, 0, 0
                e.fx, e.fy, e.curl = -p.x * scale, -p.y * scale, 0.0
                req.count += 1
            seq += 1
            stamp = now_ns()
            req.protocol_version, req.seq, req.stamp_ns, req.deadline_ns = version, seq, stamp, stamp + 300_000_000
            sample = requests.loan_uninit()
            ctypes.memmove(sample.payload_ptr, ctypes.byref(req), ctypes.sizeof(ForceRequest))
            sample.assume_init().send()
            sent[seq] = stamp
            inbox.notify()
        if not wait(node, 0.0):
            break
    print(f"planner.py: sent {len(sent)} answered {len(answered)} refused {len(refused)} {refused[:3]}", flush=True)


def drain(subscriber, cls):
    while (sample := subscriber.receive()) is not None:
        yield copy_out(sample, cls)


def wait(node, seconds):
    """False once SIGINT or SIGTERM arrived."""
    try:
        node.wait(iox2.Duration.from_secs_f64(seconds))
        return True
    except iox2.NodeWaitFailure:
        return False


if __name__ == "__main__":
    main()
