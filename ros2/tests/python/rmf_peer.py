"""Plays RMF's side against `mapc sim --ros2 --plugins-only` with Eclipse Cyclone DDS: what
door and lift supervisors, a fleet adapter and a workcell client would send, and what they
would read back. Run inside a private network namespace (the Rust test makes it).

With `"quick": true` in the config it stops after the door (steps 1 to 3).

usage: rmf_peer.py CONFIG.json  ->  JSON results on stdout, progress on stderr"""
import json
import math
import sys
import time

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from rmf_types import Types

cfg = json.load(open(sys.argv[1], encoding="utf-8"))
T = Types(cfg["definitions"])
dp = DomainParticipant(cfg["domain_id"])
result = {"errors": []}


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def qos(depth=10, latched=False):
    return Qos(Policy.Reliability.Reliable(duration(seconds=1)),
               Policy.Durability.TransientLocal if latched else Policy.Durability.Volatile,
               Policy.History.KeepLast(depth))


def topic(name, ros_type):
    return Topic(dp, "rt" + name, T.cls(ros_type))


readers = {
    "door": DataReader(dp, topic("/door_states", "rmf_door_msgs/msg/DoorState"), qos=qos(100)),
    "lift": DataReader(dp, topic("/lift_states", "rmf_lift_msgs/msg/LiftState"), qos=qos(100)),
    "robot": DataReader(dp, topic("/robot_state", "rmf_fleet_msgs/msg/RobotState"), qos=qos(100)),
    "disp": DataReader(dp, topic("/dispenser_results", "rmf_dispenser_msgs/msg/DispenserResult"), qos=qos()),
    "clock": DataReader(dp, topic("/clock", "rosgraph_msgs/msg/Clock"),
                        qos=Qos(Policy.Reliability.BestEffort, Policy.History.KeepLast(1000))),
    "map": DataReader(dp, topic("/map", "rmf_building_map_msgs/msg/BuildingMap"), qos=qos(1, True)),
}
writers = {
    "door": DataWriter(dp, topic("/door_requests", "rmf_door_msgs/msg/DoorRequest"), qos=qos(10)),
    "lift": DataWriter(dp, topic("/lift_requests", "rmf_lift_msgs/msg/LiftRequest"), qos=qos(100)),
    "path": DataWriter(dp, topic("/robot_path_requests", "rmf_fleet_msgs/msg/PathRequest"), qos=qos()),
    "fleet": DataWriter(dp, topic("/fleet_states", "rmf_fleet_msgs/msg/FleetState"), qos=qos()),
    "disp": DataWriter(dp, topic("/dispenser_requests", "rmf_dispenser_msgs/msg/DispenserRequest"), qos=qos()),
}
last = {}  # latest state per (kind, name)
clock = []  # (wall, sim)


def pump():
    for kind, r in readers.items():
        for s in r.take(N=1000):
            if type(s).__name__ == "InvalidSample":  # a writer went away
                continue
            if kind == "clock":
                clock.append((time.monotonic(), s.clock.sec + s.clock.nanosec * 1e-9))
            elif kind == "door":
                last[("door", s.door_name)] = s
            elif kind == "lift":
                last[("lift", s.lift_name)] = s
            elif kind == "robot":
                last[("robot", s.name)] = s
            elif kind == "disp":
                last[("disp", s.request_guid)] = s
            elif kind == "map":
                last[("map",)] = s


def wait(what, cond, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        pump()
        v = cond()
        if v:
            log(f"ok: {what}")
            return v
        time.sleep(0.01)
    result["errors"].append(f"timeout: {what}")
    log(f"timeout: {what}")
    return None


def sim_now():
    return clock[-1][1] if clock else 0.0


def stamp():
    t = sim_now()
    return T.value("builtin_interfaces/msg/Time", {"sec": int(t), "nanosec": int((t % 1) * 1e9)})


# 1. Every door's state, the latched map, and our writers matched by mapc's readers.
doors = cfg["doors"]
wait("DoorState of every door", lambda: all(("door", d) in last for d in doors))
result["doors_seen"] = sorted(k[1] for k in last if k[0] == "door")
m = wait("/map", lambda: last.get(("map",)))
if m:
    result["map"] = {"name": m.name, "levels": [l.name for l in m.levels],
                     "lifts": [l.name for l in m.lifts]}
for name, w in writers.items():
    wait(f"{name} writer matched", lambda: len(w.get_matched_subscriptions()) > 0, 30)

# 2. /clock at the requested rate, over 3 s of wall time.
# Read continuously (every 5 ms) so that each sample's wall time is its arrival time.
pump()
clock.clear()
end = time.monotonic() + 3.0
while time.monotonic() < end:
    pump()
    time.sleep(0.005)
if len(clock) >= 10:
    (w0, s0), (w1, s1) = clock[0], clock[-1]
    result["clock_rate"] = (s1 - s0) / (w1 - w0)
    result["clock_samples"] = len(clock)
    result["clock_monotonic"] = all(b[1] >= a[1] for a, b in zip(clock, clock[1:]))

# 3. A door opens on request and closes again.
door = doors[0]
OPEN, CLOSED = 2, 0


def door_request(mode):
    writers["door"].write(T.value("rmf_door_msgs/msg/DoorRequest", {
        "request_time": T.plain("builtin_interfaces/msg/Time", stamp()),
        "requester_id": "door_supervisor", "door_name": door, "requested_mode": {"value": mode}}))


door_request(OPEN)
t0 = sim_now()
if wait(f"{door} open", lambda: last[("door", door)].current_mode.value == OPEN):
    result["door_open_after"] = sim_now() - t0
door_request(CLOSED)
t0 = sim_now()
if wait(f"{door} closed", lambda: last[("door", door)].current_mode.value == CLOSED):
    result["door_closed_after"] = sim_now() - t0

if cfg.get("quick"):  # doors, /map, /clock and a door opened: enough to show the link
    json.dump(result, sys.stdout)
    sys.exit(0)

# 4. The lift goes to another floor and opens its doors there.
lift, floor = cfg["lift"], cfg["lift_floor"]
writers["lift"].write(T.value("rmf_lift_msgs/msg/LiftRequest", {
    "lift_name": lift, "request_time": T.plain("builtin_interfaces/msg/Time", stamp()),
    "session_id": "lift_supervisor", "request_type": 1, "destination_floor": floor,
    "door_state": 2}))
t0 = sim_now()


def lift_there():
    s = last.get(("lift", lift))
    return s and s.current_floor == floor and s.door_state == 2 and s.motion_state == 0


if wait(f"{lift} at {floor} with doors open", lift_there):
    s = last[("lift", lift)]
    result["lift"] = {"floor": s.current_floor, "door_state": s.door_state,
                      "session_id": s.session_id, "after": sim_now() - t0}

# 5. A path along the lanes to the dispenser's waypoint; RobotState follows it.
robot, fleet = cfg["robot"], cfg["fleet"]
start = wait("RobotState", lambda: last.get(("robot", robot)))
graph = m.levels[0].nav_graphs[0] if m else None
path_names = cfg["path"]
if graph and start:
    nodes = {v.name: v for v in graph.vertices}
    locs = []
    for i, n in enumerate(path_names):
        v = nodes[n]
        locs.append({"t": T.plain("builtin_interfaces/msg/Time", stamp()), "x": v.x, "y": v.y,
                     "yaw": 0.0, "obey_approach_speed_limit": False, "approach_speed_limit": 0.0,
                     "level_name": start.location.level_name, "index": i})
    writers["path"].write(T.value("rmf_fleet_msgs/msg/PathRequest", {
        "fleet_name": fleet, "robot_name": robot, "path": locs, "task_id": "mapc-test-7"}))
    end = nodes[path_names[-1]]
    t0 = sim_now()
    track = []

    def arrived():
        s = last[("robot", robot)]
        track.append((s.location.x, s.location.y))
        return (s.task_id == "mapc-test-7" and len(s.path) == 0
                and math.hypot(s.location.x - end.x, s.location.y - end.y) < 0.05)

    if wait(f"{robot} at {path_names[-1]}", arrived, 120):
        s = last[("robot", robot)]
        result["path"] = {"task_id": s.task_id, "x": s.location.x, "y": s.location.y,
                          "end": [end.x, end.y], "after": sim_now() - t0,
                          "distinct_positions": len(set(track))}

# 6. The dispenser there serves the robot's fleet.
writers["fleet"].write(T.value("rmf_fleet_msgs/msg/FleetState", {
    "name": fleet, "robots": [T.plain("rmf_fleet_msgs/msg/RobotState", last[("robot", robot)])]}))
time.sleep(0.5)
writers["disp"].write(T.value("rmf_dispenser_msgs/msg/DispenserRequest", {
    "time": T.plain("builtin_interfaces/msg/Time", stamp()), "request_guid": "disp-1",
    "target_guid": cfg["dispenser"], "transporter_type": fleet,
    "items": [{"type_guid": "medicine", "quantity": 1, "compartment_name": ""}]}))


def final_result():
    s = last.get(("disp", "disp-1"))
    return s if s and s.status != 0 else None


r = wait("dispenser result", final_result)
if r:
    result["dispenser"] = {"status": r.status, "source": r.source_guid}
json.dump(result, sys.stdout)
