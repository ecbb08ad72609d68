"""Gather every part towards the plate's centre at most 2 cm/s: the Python
twin of examples/own-planner/gather.rs. It sleeps until vision
announces new part states, and learns the rig from RigInfo (no config file).

    UPM_PREFIX=upm_run_1234_ python gather.py [--prefix P] [--duration S]
"""
import argparse
import math
import os

import upm_ipc

MASS = 0.1 / (0.25 * 9.81)  # kg, as the Rust example
MAX_FORCE = 0.01  # N


def plan(states, out, max_force):
    """m·8·(v_desired − v) towards (0, 0), clamped to max_force."""
    out.clear()
    for p in states.used():
        dx, dy = -p.x, -p.y
        d = max(math.hypot(dx, dy), 1e-9)
        speed = min(0.5 * d, 0.02)
        fx = MASS * 8.0 * (speed * dx / d - p.vx)
        fy = MASS * 8.0 * (speed * dy / d - p.vy)
        n = math.hypot(fx, fy)
        s = max_force / n if n > max_force else 1.0
        if not out.push_force(p.id, fx * s, fy * s):
            break
    return out.count > 0


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--prefix", default=os.environ.get("UPM_PREFIX", "upm_"))
    ap.add_argument("--duration", type=float, help="seconds (default: until Ctrl-C)")
    args = ap.parse_args()
    rig = upm_ipc.connect(args.prefix)
    info = rig.rig_info(timeout=5.0)
    max_force = MAX_FORCE
    if info is not None:
        # A quarter of the most a lone part can get: room for the others.
        max_force = min(MAX_FORCE, 0.25 * info.max_part_force_n)
        print(f"gather.py: rig {info.prefix_str()!r}: mu_m_g {info.mu_m_g} N, {info.count} centers, "
              f"parts at {info.vision_frame_hz} Hz, at most {info.max_part_force_n:.4f} N a part", flush=True)
    end = None if args.duration is None else upm_ipc.monotonic_now_ns() + int(args.duration * 1e9)
    req, sent = upm_ipc.ForceRequest(), 0
    while end is None or upm_ipc.monotonic_now_ns() < end:
        woken = rig.wait_part_states(0.1)
        if woken is None:  # SIGINT / SIGTERM
            break
        # Also after a timeout: a vision that does not notify is read at 10 Hz.
        states = rig.newest_part_states()
        if states is not None and plan(states, req, max_force):
            now = upm_ipc.monotonic_now_ns()
            sent += 1
            req.seq, req.stamp_ns = sent, now
            req.deadline_ns = now + upm_ipc.REQUEST_LIFETIME_NS
            rig.send_request(req)
        for refusal in rig.rejections(mine=True):  # why the core refused one of ours
            print(f"gather.py: {refusal}", flush=True)
    rig.close()
    print(f"gather.py: {sent} requests")


if __name__ == "__main__":
    main()
