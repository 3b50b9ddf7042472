"""Plays an RMF door supervisor on rmw_zenoh's wire format against `mapc sim --ros2 --rmw
zenoh --plugins-only`, with Zenoh's own Python package (eclipse-zenoh): a peer of the
router on tcp/localhost:7447, as rmw_zenoh_cpp's sessions are. The type hashes in its key
expressions are the ones rosidl generated for ROS 2 (given in the config), not mapc's; CDR
through Cyclone DDS's Python encoder (rmf_types.py); the GID check through the xxhash
package (XXH3-128, the hash rmw_zenoh_cpp derives GIDs with).

usage: zenoh_peer.py CONFIG.json  ->  JSON results on stdout, progress on stderr"""
import json
import re
import struct
import sys
import time

import xxhash
import zenoh
import zenoh.ext

from rmf_types import Types

cfg = json.load(open(sys.argv[1], encoding="utf-8"))
T = Types(cfg["definitions"])
D = cfg["domain_id"]
H = cfg["hashes"]  # ROS type -> RIHS01_... as ROS 2 publishes it
result = {"errors": []}


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def key(topic, ros_type, hash_=None):
    pkg, _, name = ros_type.split("/")
    return f"{D}/{topic}/{pkg}::msg::dds_::{name}_/{hash_ or H[ros_type]}"


conf = zenoh.Config()
conf.insert_json5("mode", '"peer"')
conf.insert_json5("connect/endpoints", '["tcp/localhost:7447"]')
conf.insert_json5("scouting/multicast/enabled", "false")
session = zenoh.open(conf)

samples = {"door": [], "clock": [], "map": []}


def on(kind):
    def cb(s):
        samples[kind].append((time.monotonic(), str(s.key_expr), s.payload.to_bytes(),
                              s.attachment.to_bytes() if s.attachment is not None else None))
    return cb


subs = [
    session.declare_subscriber(key("door_states", "rmf_door_msgs/msg/DoorState"), on("door")),
    session.declare_subscriber(key("clock", "rosgraph_msgs/msg/Clock"), on("clock")),
    # /map is transient local: a late subscription gets it from the publisher's cache, as
    # rmw_zenoh_cpp's transient-local subscriptions do (advanced subscriber with history).
    zenoh.ext.declare_advanced_subscriber(
        session, f"{D}/map/rmf_building_map_msgs::msg::dds_::BuildingMap_/*", on("map"),
        history=zenoh.ext.HistoryConfig(detect_late_publishers=True, max_samples=1)),
]


def decode(ros_type, payload):
    return T.cls(ros_type).deserialize(payload)


def wait(what, cond, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        v = cond()
        if v:
            log(f"ok: {what}")
            return v
        time.sleep(0.02)
    result["errors"].append(f"timeout: {what}")
    log(f"timeout: {what}")
    return None


def door_state(name):
    for _, _, p, _ in reversed(samples["door"]):
        s = decode("rmf_door_msgs/msg/DoorState", p)
        if s.door_name == name:
            return s
    return None


# 1. Every door's state, /clock advancing, the latched /map.
doors = cfg["doors"]
wait("DoorState of every door", lambda: all(door_state(d) for d in doors))
result["doors_seen"] = sorted({decode("rmf_door_msgs/msg/DoorState", p).door_name
                               for _, _, p, _ in samples["door"]})
m = wait("/map", lambda: samples["map"])
if m:
    _, k, p, _ = m[0]
    bm = decode("rmf_building_map_msgs/msg/BuildingMap", p)
    result["map"] = {"key": k, "levels": [l.name for l in bm.levels]}
wait("/clock", lambda: len(samples["clock"]) >= 20)
clock = [(w, decode("rosgraph_msgs/msg/Clock", p).clock) for w, _, p, _ in samples["clock"]]
if len(clock) >= 2:
    (w0, c0), (w1, c1) = clock[0], clock[-1]
    s0, s1 = c0.sec + c0.nanosec * 1e-9, c1.sec + c1.nanosec * 1e-9
    result["clock_rate"] = (s1 - s0) / (w1 - w0)
    result["clock_monotonic"] = all(
        (b.sec, b.nanosec) >= (a.sec, a.nanosec) for (_, a), (_, b) in zip(clock, clock[1:]))

# 2. Attachments: sequence number, source timestamp (ns), GID (a sequence of 16 bytes).
atts = []
for _, _, _, a in samples["door"]:
    if a is None or len(a) != 33 or a[16] != 16:
        result["errors"].append(f"attachment {a!r}")
        break
    seq, ts = struct.unpack("<qq", a[:16])
    atts.append((seq, ts, a[17:]))
if atts:
    result["attachment"] = {
        "sequence_increasing": all(b[0] == a[0] + 1 for a, b in zip(atts, atts[1:])),
        "first_sequence": atts[0][0],
        "timestamp_age_s": time.time() - atts[-1][1] * 1e-9,
        "gid": atts[0][2].hex(),
        "one_gid": len({g for _, _, g in atts}) == 1,
    }

# 3. Liveliness tokens: mapc's node, publishers and subscriptions.
# Asked again if the answer is empty: a query can reach the router before the tokens
# mapc declared have (a CI run saw none once, with door states already flowing).
tokens = []
for _ in range(5):
    tokens = [str(r.ok.key_expr) for r in session.liveliness().get(f"@ros2_lv/{D}/**", timeout=5)
              if r.ok is not None]
    if tokens:
        break
    time.sleep(0.5)
result["tokens"] = sorted(tokens)
door_pub = [t for t in tokens if "/MP/" in t and "/%door_states/" in t]
if door_pub and atts:
    # rmw_zenoh_cpp's GID: XXH3-128 of the liveliness key expression, low 64 bits first.
    h = xxhash.xxh3_128_intdigest(door_pub[0].encode())
    result["attachment"]["gid_is_xxh3_of_token"] = h.to_bytes(16, "little").hex() == result["attachment"]["gid"]

# 4. A door opens on request (a DoorRequest with rmw_zenoh's attachment).
door = doors[0]
OPEN = 2
pub = session.declare_publisher(key("door_requests", "rmf_door_msgs/msg/DoorRequest"))
gid = bytes(range(1, 17))
t = clock[-1][1] if clock else None
req = T.value("rmf_door_msgs/msg/DoorRequest", {
    "request_time": {"sec": t.sec if t else 0, "nanosec": t.nanosec if t else 0},
    "requester_id": "door_supervisor", "door_name": door, "requested_mode": {"value": OPEN}})
time.sleep(0.5)  # let mapc's subscription learn of this publisher
pub.put(req.serialize(), attachment=struct.pack("<qq", 1, time.time_ns()) + bytes([16]) + gid)
if wait(f"{door} open", lambda: (s := door_state(door)) and s.current_mode.value == OPEN, 30):
    result["door_opened"] = True

session.close()
json.dump(result, sys.stdout)
