"""For each sample of input.json: Cyclone DDS serialises the same values (bytes returned
as hex) and deserialises mapc's bytes (values returned as JSON).

usage: cdr_check.py INPUT.json  ->  JSON on stdout"""
import json
import sys

from rmf_types import Types

data = json.load(open(sys.argv[1], encoding="utf-8"))
types_ = Types(data["definitions"])
out = {}
for s in data["samples"]:
    name = s["name"]
    try:
        cls = types_.cls(name)
        value = types_.value(name, s["value"])
        cyclone = value.serialize()
        decoded = cls.deserialize(bytes.fromhex(s["mapc"]))
        out[name] = {"cyclone": cyclone.hex(), "decoded": types_.plain(name, decoded)}
    except Exception as e:  # reported per type, the test names it
        out[name] = {"error": f"{type(e).__name__}: {e}"}
json.dump(out, sys.stdout)
