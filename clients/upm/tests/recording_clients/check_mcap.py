"""Read a `upm run` recording with the `mcap` package (PyPI), a reader
nobody in this project wrote, and check what the recorder promises
(clients/recorder/src/rig_log.rs): the `upm` profile, a raw channel per
service with traffic plus its `/json` companion, `upm/scene` and
`upm/latency`, per-topic counts equal to the `upm.recorder` metadata, the
raw bytes the size the channel says, and `config.toml` attached.

usage: check_mcap.py RUN.mcap CONFIG.toml PREFIX SCENARIO

Prints what it found; exits 1 (with every failed check) if any check fails.
"""

import collections
import json
import sys

from mcap.reader import make_reader

RAW_ENCODING = "upm-repr-c"
# Every service the recorder subscribes to.
SERVICES = [
    "upm/part_states",
    "upm/force_request",
    "upm/explicit_schedule",
    "upm/core_command",
    "upm/pick",
    "upm/recipe",
    "upm/recipe/active",
    "upm/line",
    "upm/schedule",
    "upm/telemetry",
    "upm/rejection",
    "upm/sim/ground_truth",
    "upm/camera/frame",
]
# The services a sort run with the truth camera has traffic on.
MUST_HAVE_TRAFFIC = [
    "upm/part_states",
    "upm/force_request",
    "upm/schedule",
    "upm/telemetry",
    "upm/sim/ground_truth",
]

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
    return ok


def main():
    path, config_path, prefix, scenario = sys.argv[1:5]
    with open(config_path, "rb") as f:
        config_text = f.read()
    with open(path, "rb") as f:
        reader = make_reader(f)
        header = reader.get_header()
        summary = reader.get_summary()
        metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
        attachments = {a.name: a for a in reader.iter_attachments()}
        counts = collections.Counter()
        first = {}
        raw_sizes = collections.defaultdict(set)
        log_times = collections.defaultdict(list)
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            counts[channel.topic] += 1
            first.setdefault(channel.topic, (schema, channel, message))
            log_times[channel.topic].append(message.log_time)
            if channel.message_encoding == RAW_ENCODING:
                raw_sizes[channel.topic].add(len(message.data))

    print(f"header: profile={header.profile!r} library={header.library!r}")
    check(header.profile == "upm", f"profile is {header.profile!r}, not 'upm'")
    check(summary is not None, "no summary section")
    channels = {c.topic: c for c in summary.channels.values()}
    schemas = summary.schemas
    print(f"channels: {len(channels)}, messages: {sum(counts.values())}")
    for topic in sorted(channels):
        c = channels[topic]
        s = schemas.get(c.schema_id)
        print(
            f"  {topic}: {counts[topic]} messages, encoding {c.message_encoding}, "
            f"schema {s.name if s else None} ({s.encoding if s else None}), metadata {dict(c.metadata)}"
        )

    # The summary's statistics agree with what is in the file.
    if summary.statistics is not None:
        by_topic = {
            summary.channels[cid].topic: n for cid, n in summary.statistics.channel_message_counts.items()
        }
        check(
            by_topic == dict(counts),
            f"statistics' counts {by_topic} differ from the messages read {dict(counts)}",
        )
        check(
            summary.statistics.message_count == sum(counts.values()),
            f"statistics' message_count {summary.statistics.message_count} != {sum(counts.values())}",
        )
    else:
        check(False, "no statistics record")

    # Run metadata.
    run = metadata.get("upm")
    print(f"metadata upm: {run}")
    if check(run is not None, "no 'upm' metadata record"):
        for key in ["protocol_version", "prefix", "scenario", "seed", "unix_at_start_ns"]:
            check(key in run, f"'upm' metadata lacks {key}")
        check(run.get("prefix") == prefix, f"'upm' metadata prefix {run.get('prefix')!r} != {prefix!r}")
        check(run.get("scenario") == scenario, f"'upm' metadata scenario {run.get('scenario')!r} != {scenario!r}")
        start = int(run.get("unix_at_start_ns", "0"))
        # Log times are Unix ns from the recorder's start.
        for topic, times in log_times.items():
            check(min(times) >= start, f"{topic}: a log time {min(times)} before the recorder started ({start})")

    rec = metadata.get("upm.recorder")
    print(f"metadata upm.recorder: {rec}")
    check(rec is not None, "no 'upm.recorder' metadata record")
    rec = rec or {}
    if check("lost_total" in rec, "'upm.recorder' lacks lost_total"):
        # "unknown" where the recorder cannot tell (schedule, rejection, truth).
        lost = sum(int(v) for v in (rec.get(f"lost {t}", "0") for t in SERVICES) if v != "unknown")
        check(int(rec["lost_total"]) == lost, f"lost_total {rec['lost_total']} != sum of lost per topic {lost}")

    # Raw channels, their JSON companions and the counts.
    for topic in SERVICES:
        received = rec.get(f"received {topic}")
        check(f"lost {topic}" in rec, f"'upm.recorder' lacks 'lost {topic}'")
        if not check(received is not None, f"'upm.recorder' lacks 'received {topic}'"):
            continue
        check(
            counts[topic] == int(received),
            f"{topic}: {counts[topic]} messages in the file, the recorder says it received {received}",
        )
        if topic in MUST_HAVE_TRAFFIC:
            check(counts[topic] > 0, f"{topic}: no traffic in a {scenario} run")
        if counts[topic] == 0:
            continue
        raw = channels.get(topic)
        if not check(raw is not None, f"{topic}: messages but no channel"):
            continue
        s = schemas.get(raw.schema_id)
        check(raw.message_encoding == RAW_ENCODING, f"{topic}: message encoding {raw.message_encoding}")
        check(s is not None and s.encoding == RAW_ENCODING, f"{topic}: schema encoding {s and s.encoding}")
        type_name = raw.metadata.get("type_name")
        check(s is not None and s.name == type_name, f"{topic}: schema name {s and s.name} != type_name {type_name}")
        check(type_name is not None and type_name.startswith("upm::"), f"{topic}: type_name {type_name}")
        size = int(raw.metadata.get("size", "-1"))
        # A frame's pixels follow its header when frame_pixels is set.
        pixels = topic == "upm/camera/frame" and (run or {}).get("frame_pixels") == "true"
        check(
            pixels or raw_sizes[topic] == {size},
            f"{topic}: raw message lengths {sorted(raw_sizes[topic])} but the channel's size is {size}",
        )
        js = channels.get(topic + "/json")
        if not check(js is not None, f"{topic}: no {topic}/json companion"):
            continue
        jss = schemas.get(js.schema_id)
        check(js.message_encoding == "json", f"{topic}/json: message encoding {js.message_encoding}")
        check(jss is not None and jss.encoding == "jsonschema", f"{topic}/json: schema encoding {jss and jss.encoding}")
        check(jss is not None and jss.name == type_name, f"{topic}/json: schema name {jss and jss.name}")
        check(counts[topic + "/json"] > 0, f"{topic}/json: no messages")
        if jss is not None and topic + "/json" in first:
            properties = set(json.loads(jss.data).get("properties", {}))
            keys = set(json.loads(first[topic + "/json"][2].data))
            check(keys <= properties, f"{topic}/json: keys {sorted(keys - properties)} not in its schema")

    # A decoded part states message.
    if check("upm/part_states/json" in first, "no upm/part_states/json message"):
        m = json.loads(first["upm/part_states/json"][2].data)
        parts = m.get("parts")
        if check(isinstance(parts, list) and parts, f"upm/part_states/json: no parts: {m}"):
            check(len(parts) == m.get("count"), f"upm/part_states/json: {len(parts)} parts, count {m.get('count')}")
            for p in parts:
                check(
                    isinstance(p.get("x"), (int, float)) and isinstance(p.get("y"), (int, float)),
                    f"upm/part_states/json: a part without x/y: {p}",
                )
            print(f"upm/part_states/json: {len(parts)} parts, first at x={parts[0]['x']:.4f} y={parts[0]['y']:.4f}")

    # The raw schedule is a whole Schedule.
    sched = channels.get("upm/schedule")
    if check("upm/schedule" in first and sched is not None, "no raw upm/schedule message"):
        n = len(first["upm/schedule"][2].data)
        size = int(sched.metadata.get("size", "-1"))
        check(n == size, f"raw upm/schedule message is {n} bytes, the channel's size says {size}")
        print(f"upm/schedule: raw message {n} bytes, channel size {size}")
    if check("upm/schedule/json" in first, "no upm/schedule/json message"):
        m = json.loads(first["upm/schedule/json"][2].data)
        check(isinstance(m.get("residual"), (int, float)), f"upm/schedule/json has no residual: {m}")

    # Scene and latency (what docs/foxglove-layout.json shows).
    scene = channels.get("upm/scene")
    if check(scene is not None and counts["upm/scene"] > 0, "no upm/scene messages"):
        s = schemas.get(scene.schema_id)
        check(scene.message_encoding == "protobuf", f"upm/scene: encoding {scene.message_encoding}")
        check(s is not None and s.name == "foxglove.SceneUpdate", f"upm/scene: schema {s and s.name}")
        check(b"plate" in first["upm/scene"][2].data, "upm/scene: no entity in frame 'plate'")
    latency = channels.get("upm/latency")
    if check(latency is not None and counts["upm/latency"] > 0, "no upm/latency messages"):
        check(latency.message_encoding == "json", f"upm/latency: encoding {latency.message_encoding}")
        m = json.loads(first["upm/latency"][2].data)
        for k in ["motor_wakeup", "solver"]:
            check(isinstance(m.get(k, {}).get("p99_us"), (int, float)), f"upm/latency: no {k}.p99_us: {m}")
        print(f"upm/latency: first {json.dumps(m)[:200]}")

    # The rig's TOML, attached whole.
    att = attachments.get("config.toml")
    if check(att is not None, f"no config.toml attachment (attachments: {sorted(attachments)})"):
        print(f"attachment config.toml: {len(att.data)} bytes, {att.media_type}")
        check(bytes(att.data) == config_text, "the attached config.toml differs from the run's config.toml")

    if failures:
        print(f"{len(failures)} check(s) failed:")
        for f in failures:
            print(f"  FAIL {f}")
        sys.exit(1)
    print("all checks passed")


main()
