"""A robot on OPC UA, written against docs/line.md with asyncua only.

usage: robot_opcua.py URL USER PASSWORD SECONDS [SERVER_PKI_DIR [RECIPE BAD_RECIPE]]
Prints one JSON object: what it read, picked and was refused. With the
server's PKI directory it also connects over Basic256Sha256
SignAndEncrypt: refused until its certificate is trusted, then served.
With RECIPE (a name) and BAD_RECIPE (a path), it switches the cell to
RECIPE halfway through its pick loop, after being refused BAD_RECIPE.
"""
import asyncio
import json
import shutil
import socket
import sys
import tempfile
import time
from pathlib import Path

from asyncua import Client, ua

URL, USER, PASSWORD, SECONDS = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
SERVER_PKI = Path(sys.argv[5]) if len(sys.argv) > 5 else None
RECIPE, BAD_RECIPE = (sys.argv[6], sys.argv[7]) if len(sys.argv) > 7 else (None, None)
out = {}


def code(e):
    return type(e).__name__


async def refused(coro):
    """The status code name of a call that must fail, or 'Good'."""
    try:
        await coro
        return "Good"
    except ua.UaStatusCodeError as e:
        return code(e)


async def anonymous():
    async with Client(URL) as c:
        ns = await c.get_namespace_index("urn:upm:rig")
        node = lambda s: c.get_node(f"ns={ns};s=Rig.{s}")
        out["namespace_index"] = ns
        for name in ["State", "Health", "Recipe", "Picked", "Lost", "PartsPerMinute"]:
            out[name] = await node(name).read_value()
        poses = []
        for n in range(16):
            try:
                poses.append({k: await node(f"Pick.{n}.{k}").read_value()
                              for k in ["Ready", "Class", "PartId", "X", "Y", "Theta"]})
            except ua.UaStatusCodeError:
                break
        out["poses"] = poses
        rig = c.get_node(f"ns={ns};s=Rig")
        out["anonymous_stop"] = await refused(rig.call_method(f"{ns}:Stop"))
        out["anonymous_picked"] = await refused(
            rig.call_method(f"{ns}:Picked", ua.Variant(0, ua.VariantType.UInt32)))
        out["anonymous_load"] = await refused(
            rig.call_method(f"{ns}:LoadRecipe", ua.Variant("default", ua.VariantType.String)))
        # Values change by subscription at the camera's rate.
        changes = []

        class Handler:
            def datachange_notification(self, node, val, data):
                changes.append(val)

        sub = await c.create_subscription(50, Handler())
        await sub.subscribe_data_change(node("PartsPerMinute"))
        await sub.subscribe_data_change(node("Pick.0.Ready"))
        await asyncio.sleep(3)
        out["subscription_notifications"] = len(changes)
        await sub.delete()


async def wrong_password():
    c = Client(URL)
    c.set_user(USER)
    c.set_password(PASSWORD + "x")
    try:
        await c.connect()
        await c.disconnect()
        out["wrong_password"] = "Good"
    except Exception as e:  # asyncua raises the ActivateSession fault
        out["wrong_password"] = code(e) if isinstance(e, ua.UaStatusCodeError) else str(e)


async def robot():
    c = Client(URL)
    c.set_user(USER)
    c.set_password(PASSWORD)
    async with c:
        ns = await c.get_namespace_index("urn:upm:rig")
        node = lambda s: c.get_node(f"ns={ns};s=Rig.{s}")
        rig = c.get_node(f"ns={ns};s=Rig")
        picked = lambda v: rig.call_method(f"{ns}:Picked", v)
        u32 = lambda n: ua.Variant(n, ua.VariantType.UInt32)
        n_poses = len(out["poses"])
        out["out_of_range"] = await refused(picked(u32(n_poses)))
        out["far_out_of_range"] = await refused(picked(u32(2**32 - 1)))
        out["string_pose"] = await refused(picked(ua.Variant("0", ua.VariantType.String)))
        out["int64_pose"] = await refused(picked(ua.Variant(0, ua.VariantType.Int64)))
        out["no_pose"] = await refused(rig.call_method(f"{ns}:Picked"))
        out["two_poses"] = await refused(rig.call_method(f"{ns}:Picked", u32(0), u32(1)))
        out["stop_with_argument"] = await refused(rig.call_method(f"{ns}:Stop", u32(1)))
        # The pick loop: take what is ready, note what is refused.
        counts = {"good": 0, "raced": 0, "other": {}, "not_ready": None}

        async def pick_for(seconds, n_poses):
            t0 = time.time()
            while time.time() - t0 < seconds:
                for n in range(n_poses):
                    ready = await node(f"Pick.{n}.Ready").read_value()
                    if not ready and counts["not_ready"] is None:
                        counts["not_ready"] = await refused(picked(u32(n)))
                        continue
                    if not ready:
                        continue
                    r = await refused(picked(u32(n)))
                    if r == "Good":
                        counts["good"] += 1
                    elif r == "BadInvalidState":
                        counts["raced"] += 1
                    else:
                        counts["other"][r] = counts["other"].get(r, 0) + 1
                await asyncio.sleep(0.03)

        if RECIPE is None:
            await pick_for(SECONDS, n_poses)
        else:
            await pick_for(SECONDS / 2, n_poses)
            load = lambda v: rig.call_method(f"{ns}:LoadRecipe", v)
            text = lambda t: ua.Variant(t, ua.VariantType.String)
            out["load_unknown"] = await refused(load(text("no-such-recipe")))
            out["load_unknown_error"] = await node("RecipeError").read_value()
            out["load_other_parts"] = await refused(load(text(BAD_RECIPE)))
            out["load_other_parts_error"] = await node("RecipeError").read_value()
            out["load_int"] = await refused(load(ua.Variant(3, ua.VariantType.Int32)))
            out["load_nothing"] = await refused(rig.call_method(f"{ns}:LoadRecipe"))
            out["recipe_after_refusals"] = await node("Recipe").read_value()
            out["picks_before_changeover"] = counts["good"]
            out["load"] = await refused(load(text(RECIPE)))
            out["recipe_after_load"] = await node("Recipe").read_value()
            out["recipe_error_after_load"] = await node("RecipeError").read_value()
            await asyncio.sleep(0.5)
            out["pose_count_after_load"] = await node("PoseCount").read_value()
            out["pose0_after_load"] = [await node(f"Pick.0.{k}").read_value() for k in ["X", "Y"]]
            out["pose3_ready_after_load"] = await node("Pick.3.Ready").read_value()
            await pick_for(SECONDS / 2, out["pose_count_after_load"])
        out["picks_good"] = counts["good"]
        out["picks_raced"] = counts["raced"]
        out["picks_other"] = counts["other"]
        out["not_ready_pose"] = counts["not_ready"]
        # Stop and start: the state follows.
        out["stop"] = await refused(rig.call_method(f"{ns}:Stop"))
        await asyncio.sleep(2.0)
        out["state_after_stop"] = await node("State").read_value()
        out["start"] = await refused(rig.call_method(f"{ns}:Start"))
        await asyncio.sleep(2.0)
        out["state_after_start"] = await node("State").read_value()
        out["resume"] = await refused(rig.call_method(f"{ns}:Resume"))
        out["picked_after"] = await node("Picked").read_value()
        for k in ["LoginFailures", "AccessDenied", "BadArguments", "InvalidState", "RecipesLoaded",
                  "RecipesRefused"]:
            out[f"Line.{k}"] = await node(f"Line.{k}").read_value()


async def secure_session(cert, key):
    c = Client(URL)
    c.set_user(USER)
    c.set_password(PASSWORD)
    c.application_uri = "urn:upm:rig:robot"  # the URI in the client's certificate
    await c.set_security_string(f"Basic256Sha256,SignAndEncrypt,{cert},{key}")
    async with c:
        ns = await c.get_namespace_index("urn:upm:rig")
        rig = c.get_node(f"ns={ns};s=Rig")
        return (await c.get_node(f"ns={ns};s=Rig.State").read_value(),
                await refused(rig.call_method(f"{ns}:Resume")))


async def secure():
    from asyncua.crypto.cert_gen import setup_self_signed_certificate
    from cryptography.x509.oid import ExtendedKeyUsageOID
    tmp = Path(tempfile.mkdtemp())
    cert, key = tmp / "robot.der", tmp / "robot.pem"
    await setup_self_signed_certificate(key, cert, "urn:upm:rig:robot", socket.gethostname(),
                                        [ExtendedKeyUsageOID.CLIENT_AUTH], {"commonName": "upm-test-robot"})
    try:
        await secure_session(cert, key)
        out["secure_untrusted"] = "Good"
    except Exception as e:
        out["secure_untrusted"] = code(e) if isinstance(e, ua.UaStatusCodeError) else type(e).__name__
    # The operator trusts it: the server put it in rejected/.
    rejected = list((SERVER_PKI / "rejected").glob("*"))
    out["secure_rejected_files"] = len(rejected)
    (SERVER_PKI / "trusted").mkdir(parents=True, exist_ok=True)
    for f in rejected:
        shutil.move(str(f), SERVER_PKI / "trusted" / f.name)
    out["secure_state"], out["secure_resume"] = await secure_session(cert, key)
    shutil.rmtree(tmp)


async def main():
    await anonymous()
    await wrong_password()
    if SERVER_PKI is not None:
        await secure()
    await robot()
    print(json.dumps(out))


asyncio.run(main())
