"""Listens, as rmf-web's dashboard or a recorder would, to every topic a full
`mapc sim --ros2` run publishes, until the file DONE exists (mapc has exited), then half a
second more.

usage: rmf_watch.py CONFIG.json DONE  ->  JSON on stdout: per topic the messages seen, in order
CONFIG: {"definitions": {type: .msg}, "domain_id": N, "topics": {"/name": "pkg/msg/Type"}}"""
import json
import os
import sys
import time

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from rmf_types import Types

cfg = json.load(open(sys.argv[1], encoding="utf-8"))
done = sys.argv[2]
T = Types(cfg["definitions"])
dp = DomainParticipant(cfg["domain_id"])
# Reliable, volatile, deep enough for a fast run's bursts (the writers are keep-last).
qos = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.History.KeepLast(5000))
readers = {n: (ty, DataReader(dp, Topic(dp, "rt" + n, T.cls(ty)), qos=qos))
           for n, ty in cfg["topics"].items()}
seen = {n: [] for n in readers}
print("listening", file=sys.stderr, flush=True)
end = None
hard_end = time.monotonic() + 120
while time.monotonic() < hard_end:
    for n, (ty, r) in readers.items():
        for s in r.take(N=5000):
            if type(s).__name__ != "InvalidSample":  # a writer went away
                seen[n].append(T.plain(ty, s))
    if end is None and os.path.exists(done):
        end = time.monotonic() + 0.5
    if end is not None and time.monotonic() > end:
        break
    time.sleep(0.01)
json.dump(seen, sys.stdout)
