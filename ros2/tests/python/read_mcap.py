"""Reads a mapc MCAP file with the independent Python readers (`mcap`, `mcap-ros2-support`)
and compares every message with the JSON trace of the same run.

usage: read_mcap.py RUN.mcap TRACE.jsonl
Prints one JSON object: counts per topic, schemas found, the mismatches (at most 20), and
`/clock` (not in the trace): its stamps, each checked against the message's log time.
"""
import json
import math
import sys

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory


def same(trace_value, ros_value, path, out):
    """Compares a trace value (f64 numbers) with a decoded ROS value (f32 where ROS says)."""
    if isinstance(trace_value, dict):
        for k, v in trace_value.items():
            if isinstance(ros_value, dict):
                if k not in ros_value:
                    out.append(f"{path}.{k}: missing in the MCAP message")
                    continue
                same(v, ros_value[k], f"{path}.{k}", out)
                continue
            if not hasattr(ros_value, k):
                out.append(f"{path}.{k}: missing in the MCAP message")
                continue
            same(v, getattr(ros_value, k), f"{path}.{k}", out)
    elif isinstance(trace_value, list):
        ros_list = list(ros_value)
        if len(trace_value) != len(ros_list):
            out.append(f"{path}: {len(trace_value)} items in the trace, {len(ros_list)} in MCAP")
            return
        for i, (a, b) in enumerate(zip(trace_value, ros_list)):
            same(a, b, f"{path}[{i}]", out)
    elif isinstance(trace_value, bool) or isinstance(trace_value, str):
        if trace_value != ros_value:
            out.append(f"{path}: {trace_value!r} != {ros_value!r}")
    elif isinstance(trace_value, (int, float)):
        # float32 fields keep 24 bits of mantissa
        tol = max(1e-6, abs(trace_value) * 1e-6)
        if not math.isclose(float(trace_value), float(ros_value), rel_tol=1e-6, abs_tol=tol):
            out.append(f"{path}: {trace_value!r} != {ros_value!r}")
    else:
        out.append(f"{path}: unexpected trace value {trace_value!r}")


def main():
    mcap_path, trace_path = sys.argv[1], sys.argv[2]
    trace = [json.loads(l) for l in open(trace_path, encoding="utf-8")]
    result = {"schemas": {}, "topics": {}, "messages": 0, "mismatches": [], "profile": None}
    with open(mcap_path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        header = reader.get_header()
        result["profile"] = header.profile
        summary = reader.get_summary()
        for s in summary.schemas.values():
            result["schemas"][s.name] = s.encoding
        qos = {}
        for c in summary.channels.values():
            qos[c.topic] = c.metadata.get("offered_qos_profiles", "")
        result["qos"] = qos
        i = 0
        clock = []
        for schema, channel, message, ros in reader.iter_decoded_messages(log_time_order=False):
            topic = channel.topic
            result["topics"][topic] = result["topics"].get(topic, 0) + 1
            result["messages"] += 1
            if topic == "/map":
                result["map_levels"] = [
                    {"name": l.name, "doors": [d.name for d in l.doors],
                     "graphs": [(len(g.vertices), len(g.edges)) for g in l.nav_graphs]}
                    for l in ros.levels]
                result["map_lifts"] = [l.name for l in ros.lifts]
                continue
            if topic == "/clock":
                stamp = ros.clock.sec * 1_000_000_000 + ros.clock.nanosec
                if stamp != message.log_time and len(result["mismatches"]) < 20:
                    result["mismatches"].append(f"/clock {stamp} at log time {message.log_time}")
                clock.append(stamp)
                continue
            if i >= len(trace):
                result["mismatches"].append(f"message {result['messages']}: beyond the trace")
                continue
            line = trace[i]
            i += 1
            out = []
            if line["topic"] != topic:
                out.append(f"topic {line['topic']} != {topic}")
            elif abs(line["t"] * 1e9 - message.log_time) > 1:
                out.append(f"log_time {message.log_time} != t {line['t']}")
            elif topic == "/task_events":
                same(line["msg"], json.loads(ros.data), "msg", out)
            else:
                same(line["msg"], ros, "msg", out)
            if out and len(result["mismatches"]) < 20:
                result["mismatches"].append({"line": i, "topic": topic, "diff": out[:5]})
        if i != len(trace):
            result["mismatches"].append(f"{len(trace) - i} trace lines not in the MCAP")
        gaps = [b - a for a, b in zip(clock, clock[1:])]
        result["clock"] = {"count": len(clock), "first_ns": clock[0] if clock else None,
                           "last_ns": clock[-1] if clock else None,
                           "min_gap_ns": min(gaps) if gaps else None,
                           "max_gap_ns": max(gaps) if gaps else None}
    json.dump(result, sys.stdout, sort_keys=True)


main()
