"""Listens, as rmf-web's dashboard would, to what a full `mapc sim --ros2` run publishes
(fleet states, task events, supervisor heartbeats, adapter requests) for a while.

usage: rmf_watch.py CONFIG.json SECONDS  ->  JSON on stdout: per topic the messages seen"""
import json
import sys
import time

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from rmf_types import Types

cfg = json.load(open(sys.argv[1], encoding="utf-8"))
T = Types(cfg["definitions"])
dp = DomainParticipant(cfg["domain_id"])
qos = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(1000))
topics = {
    "/fleet_states": "rmf_fleet_msgs/msg/FleetState",
    "/task_events": "std_msgs/msg/String",
    "/door_supervisor_heartbeat": "rmf_door_msgs/msg/SupervisorHeartbeat",
    "/adapter_door_requests": "rmf_door_msgs/msg/DoorRequest",
    "/robot_path_requests": "rmf_fleet_msgs/msg/PathRequest",
}
readers = {n: (ty, DataReader(dp, Topic(dp, "rt" + n, T.cls(ty)), qos=qos))
           for n, ty in topics.items()}
seen = {n: [] for n in topics}
end = time.monotonic() + float(sys.argv[2])
while time.monotonic() < end:
    for n, (ty, r) in readers.items():
        for s in r.take(N=1000):
            if type(s).__name__ != "InvalidSample":  # a writer went away
                seen[n].append(T.plain(ty, s))
    time.sleep(0.01)
json.dump(seen, sys.stdout)
