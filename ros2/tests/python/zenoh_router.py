"""A Zenoh router (Zenoh's own Python package, router mode), as `ros2 run rmw_zenoh_cpp
rmw_zenohd` runs one: listens on tcp/127.0.0.1:7447, multicast scouting off. Runs until
the file DONE exists. Run inside a private network namespace (the Rust test makes it).

usage: zenoh_router.py DONE  ->  `router up <zid>` on stdout once listening"""
import os
import sys
import time

import zenoh

conf = zenoh.Config()
conf.insert_json5("mode", '"router"')
conf.insert_json5("listen/endpoints", '["tcp/127.0.0.1:7447"]')
conf.insert_json5("scouting/multicast/enabled", "false")
session = zenoh.open(conf)
print(f"router up {session.zid()}", flush=True)
end = time.monotonic() + 600
while not os.path.exists(sys.argv[1]) and time.monotonic() < end:
    time.sleep(0.05)
session.close()
