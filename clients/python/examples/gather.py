"""Gather every part towards the plate's centre at most 2 cm/s: the Python
twin of clients/planner/examples/external_planner.rs.

    UPM_PREFIX=upm_run_1234_ python gather.py [--prefix P] [--duration S]
"""
import argparse
import math
import os

import upm_ipc

MASS = 0.1 / (0.25 * 9.81)  # kg, as the Rust example
MAX_FORCE = 0.01  # N


def plan(states, out):
    """m·8·(v_desired − v) towards (0, 0), clamped to MAX_FORCE."""
    out.clear()
    for p in states.used():
        dx, dy = -p.x, -p.y
        d = max(math.hypot(dx, dy), 1e-9)
        speed = min(0.5 * d, 0.02)
        fx = MASS * 8.0 * (speed * dx / d - p.vx)
        fy = MASS * 8.0 * (speed * dy / d - p.vy)
        n = math.hypot(fx, fy)
        s = MAX_FORCE / n if n > MAX_FORCE else 1.0
        if not out.push_force(p.id, fx * s, fy * s):
            break
    return out.count > 0


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--prefix", default=os.environ.get("UPM_PREFIX", "upm_"))
    ap.add_argument("--duration", type=float, help="seconds (default: until Ctrl-C)")
    args = ap.parse_args()
    rig = upm_ipc.connect(args.prefix)
    end = None if args.duration is None else upm_ipc.monotonic_now_ns() + int(args.duration * 1e9)
    req, sent = upm_ipc.ForceRequest(), 0
    while end is None or upm_ipc.monotonic_now_ns() < end:
        states = rig.newest_part_states()
        if states is not None and plan(states, req):
            now = upm_ipc.monotonic_now_ns()
            sent += 1
            req.seq, req.stamp_ns = sent, now
            req.deadline_ns = now + upm_ipc.REQUEST_LIFETIME_NS
            rig.send_request(req)
        for refusal in rig.rejections():  # why the core refused one, if it did
            print(f"gather.py: {refusal}", flush=True)
        if not rig.wait(0.001):  # SIGINT / SIGTERM
            break
    rig.close()
    print(f"gather.py: {sent} requests")


if __name__ == "__main__":
    main()
