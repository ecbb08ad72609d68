"""A PLC on Modbus TCP, written against docs/line.md with pymodbus only.

usage: plc_modbus.py HOST PORT
Prints one JSON object: the registers it read and the answers it got.
"""
import json
import socket
import sys
import time

from pymodbus.client import ModbusTcpClient
from pymodbus.exceptions import ModbusException

HOST, PORT = sys.argv[1], int(sys.argv[2])
out = {}


def exception(r):
    return r.exception_code if r.isError() else None


def s32(hi, lo):
    v = (hi << 16) | lo
    return v - (1 << 32) if v & 0x80000000 else v


c = ModbusTcpClient(HOST, port=PORT)
assert c.connect()
# The rig idles until its first schedule: wait for running (1).
t0 = time.time()
while c.read_input_registers(0, count=1).registers[0] != 1 and time.time() - t0 < 30:
    time.sleep(0.2)
out["waited_for_running_s"] = round(time.time() - t0, 1)
rig = c.read_input_registers(0, count=8).registers
out["state"], out["picked"], out["lost"] = rig[0], (rig[1] << 16) | rig[2], (rig[3] << 16) | rig[4]
out["ppm_centi"], out["poses"] = rig[5], rig[6]
poses = []
for n in range(out["poses"]):
    r = c.read_input_registers(100 + 10 * n, count=10).registers
    poses.append({"ready": r[0], "class": r[1], "x_centi_mm": s32(r[2], r[3]), "y_centi_mm": s32(r[4], r[5]),
                  "theta_milli_deg": s32(r[6], r[7]), "part_id": (r[8] << 16) | r[9]})
out["pose_list"] = poses
out["run_coil"] = c.read_coils(0, count=1).bits[0]
out["off_map"] = exception(c.read_input_registers(8, count=1))
out["across_blocks"] = exception(c.read_input_registers(5, count=100))
out["past_poses"] = exception(c.read_input_registers(260, count=1))
out["holding_read"] = exception(c.read_holding_registers(0, count=1))
out["coil_1"] = exception(c.write_coil(1, True))
out["ack_out_of_range"] = exception(c.write_register(10, 16))
# A pose with no part ready: busy (the PLC retries).
idle = [n for n, p in enumerate(poses) if not p["ready"]]
out["ack_not_ready"] = exception(c.write_register(10, idle[0])) if idle else "all ready"
out["stop"] = exception(c.write_coil(0, False))
time.sleep(2.0)
out["state_after_stop"] = c.read_input_registers(0, count=1).registers[0]
out["run_coil_after_stop"] = c.read_coils(0, count=1).bits[0]
out["start"] = exception(c.write_coil(0, True))
time.sleep(2.0)
out["state_after_start"] = c.read_input_registers(0, count=1).registers[0]
# Malformed frames: a wrong protocol id, then garbage; the server stays up.
closed = []
for frame in [b"\x00\x01\x12\x34\x00\x06\x01\x04\x00\x00\x00\x01", b"\x00\x02\x00\x00\x00\x03\x01\x85\x00"]:
    s = socket.create_connection((HOST, PORT), timeout=5)
    s.sendall(frame)
    try:
        closed.append(s.recv(100) == b"")
    except socket.timeout:
        closed.append(False)
    s.close()
out["malformed_closed"] = closed
# Many clients that connect and drop.
for _ in range(200):
    s = socket.create_connection((HOST, PORT), timeout=5)
    s.close()
# The server frees a slot when it reads a dropped client's end, so right
# after the churn it may still refuse a new client (at 64 open); a PLC
# reconnects. It must answer within 10 s.
deadline = time.monotonic() + 10.0
out["after_churn_attempts"] = 0
while True:
    out["after_churn_attempts"] += 1
    c2 = ModbusTcpClient(HOST, port=PORT)
    try:
        if c2.connect():
            out["after_churn_state"] = c2.read_input_registers(0, count=1).registers[0]
            break
    except (ConnectionError, OSError, ModbusException) as e:
        out["after_churn_error"] = repr(e)
    finally:
        c2.close()
    if time.monotonic() > deadline:
        break
    time.sleep(0.2)
c.close()
print(json.dumps(out))
