"""Fallback of live_topic.js for a machine without node/npm.

NOTE: unlike live_topic.js (Foxglove's own FoxgloveClient), this client is
OUR OWN code: it speaks the Foxglove WebSocket protocol by hand over the
`websockets` package (text ops `serverInfo`/`advertise`, our `subscribe`,
binary opcode 0x01 = u8 op, u32 subscription id, u64 log time, payload), so
it proves less about a stranger's client than the Node one does.

usage: live_topic.py URL TOPIC CONNECT_TIMEOUT_S WINDOW_MS

Prints `first message after X ms` and exits 0, or says why not and exits 1.
"""

import json
import struct
import sys
import time

from websockets.sync.client import connect

url, topic, connect_timeout_s, window_ms = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
give_up_at = time.monotonic() + connect_timeout_s
SUBSCRIPTION = 1


def fail(why):
    print(f"FAIL {why}", flush=True)
    sys.exit(1)


def session(attempt):
    # The foxglove SDK 0.30 server accepts foxglove.sdk.v1 only.
    with connect(url, subprotocols=["foxglove.sdk.v1"], open_timeout=2, max_size=None) as ws:
        subscribed_at = None
        while True:
            if subscribed_at is None:
                timeout = max(0.0, give_up_at - time.monotonic()) + 1.0
            else:
                timeout = window_ms / 1000.0 - (time.monotonic() - subscribed_at)
                if timeout <= 0:
                    fail(f"no message on {topic} within {window_ms:.0f} ms of subscribing")
            try:
                frame = ws.recv(timeout=timeout)
            except TimeoutError:
                if subscribed_at is None:
                    fail(f"{topic} never advertised")
                fail(f"no message on {topic} within {window_ms:.0f} ms of subscribing")
            if isinstance(frame, str):
                op = json.loads(frame)
                if op.get("op") == "serverInfo":
                    print(f"connected (attempt {attempt}): server {op.get('name')!r}", flush=True)
                elif op.get("op") == "advertise" and subscribed_at is None:
                    for c in op.get("channels", []):
                        if c.get("topic") == topic:
                            print(f"advertised {topic}: channel {c['id']}, encoding {c.get('encoding')}", flush=True)
                            ws.send(json.dumps(
                                {"op": "subscribe", "subscriptions": [{"id": SUBSCRIPTION, "channelId": c["id"]}]}
                            ))
                            subscribed_at = time.monotonic()
                continue
            if subscribed_at is None or len(frame) < 13 or frame[0] != 0x01:
                continue
            sub, log_time = struct.unpack_from("<IQ", frame, 1)
            if sub != SUBSCRIPTION:
                continue
            ms = (time.monotonic() - subscribed_at) * 1000.0
            m = json.loads(frame[13:])
            parts = m.get("parts")
            if not parts or not all(isinstance(p.get("x"), (int, float)) and isinstance(p.get("y"), (int, float)) for p in parts):
                fail(f"message on {topic} has no parts with x/y: {m}")
            print(f"message: seq {m.get('seq')}, {len(parts)} parts, log time {log_time} ns", flush=True)
            print(f"first message after {ms:.1f} ms", flush=True)
            sys.exit(0 if ms <= window_ms else 1)


attempt = 0
while True:
    attempt += 1
    try:
        session(attempt)
    except (OSError, ConnectionError, TimeoutError) as e:
        if time.monotonic() >= give_up_at:
            fail(f"no connection to {url} after {attempt} attempts: {e}")
        time.sleep(0.25)
    except Exception as e:  # websockets' own handshake errors (e.g. InvalidStatus)
        if type(e).__module__.startswith("websockets") and time.monotonic() < give_up_at:
            time.sleep(0.25)
            continue
        raise
