"""Observer: request -> schedule latency on a running rig, whoever the
planner is, read from the side (subscribes to upm/force_request and
upm/schedule; Schedule.seq and request_stamp_ns are those of the request
it was solved from, Schedule.stamp_ns when the core picked it up).

    python measure.py --prefix P --duration S [--json]
"""
import argparse
import json
import os
import statistics

import iceoryx2 as iox2
import upm_ipc
from upm_ipc import copy_out, open_pub_sub

ap = argparse.ArgumentParser()
ap.add_argument("--prefix", default=os.environ.get("UPM_PREFIX", "upm_"))
ap.add_argument("--duration", type=float, default=10.0)
ap.add_argument("--json", action="store_true", help="one JSON line instead of text")
args = ap.parse_args()

node = (iox2.NodeBuilder.new().config(upm_ipc.config_with_prefix(args.prefix))
        .name(iox2.NodeName.new("upm-measure-py")).create(iox2.ServiceType.Ipc))
reqs = open_pub_sub(node, upm_ipc.FORCE_REQUEST, upm_ipc.ForceRequest).subscriber_builder().create()
scheds = open_pub_sub(node, upm_ipc.SCHEDULE, upm_ipc.Schedule).subscriber_builder().create()

stamps = set()  # (seq, stamp_ns) of every request seen
core_ms, seen_ms, solve_ms = [], [], []
end = upm_ipc.monotonic_now_ns() + int(args.duration * 1e9)
while upm_ipc.monotonic_now_ns() < end:
    while (s := reqs.receive()) is not None:
        r = copy_out(s, upm_ipc.ForceRequest)
        stamps.add((r.seq, r.stamp_ns))
    while (s := scheds.receive()) is not None:
        now = upm_ipc.monotonic_now_ns()
        sc = copy_out(s, upm_ipc.Schedule)
        # By seq and stamp: history may hand us a schedule of an earlier request.
        if (sc.seq, sc.request_stamp_ns) in stamps:
            core_ms.append((sc.stamp_ns - sc.request_stamp_ns) / 1e6)  # core picked it up
            seen_ms.append((now - sc.request_stamp_ns) / 1e6)  # observer saw the schedule
            solve_ms.append(sc.solve_time_ns / 1e6)
    node.wait(iox2.Duration.from_micros(100))


def summary(xs):
    xs = sorted(xs)
    if not xs:
        return None
    return {"n": len(xs), "p50": statistics.median(xs), "p99": xs[int(0.99 * (len(xs) - 1))], "max": xs[-1]}


figures = {
    "requests": len(stamps),
    "matched": len(core_ms),
    "request_to_core_pickup_ms": summary(core_ms),
    "request_to_schedule_seen_ms": summary(seen_ms),
    "solve_ms": summary(solve_ms),
}
if args.json:
    print(json.dumps(figures))
else:
    print(f"requests seen {len(stamps)}, schedules matched {len(core_ms)}")
    for k in ("request_to_core_pickup_ms", "request_to_schedule_seen_ms", "solve_ms"):
        s = figures[k]
        if s:
            print(f"{k}: n={s['n']} p50={s['p50']:.3f} p99={s['p99']:.3f} max={s['max']:.3f}")
