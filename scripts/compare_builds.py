#!/usr/bin/env python3
"""Two or more mapc binaries side by side on the demo maps (issue 37, BENCHMARKS.md).

Every round runs each binary, in a new random order per round, on:
- `build`: `mapc build` of the seven demo maps, every target, into a fresh directory;
- per demo map, its first compile: `mapc gazebo` into a fresh directory.
Prints per case the median wall and CPU time (user + system) of each binary and the
median over rounds of the per-round ratio (binary / first binary): below 1 is faster.

    scripts/compare_builds.py --mapc OLD --mapc NEW [--rounds 9] [--work DIR] [--only build]

A --mapc value may start with NAME=VALUE words: the environment of that binary's runs
(e.g. `--mapc "RUST_LOG=x target/release/mapc"`). Run from the crate root; needs ../shared.
"""

import argparse
import os
import random
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from paths import SHARED

MAPS = ["triple_H", "battle_royale", "office", "campus", "hotel", "airport_terminal", "clinic"]


def timed(cmd, env):
    """(wall seconds, CPU seconds) of one run; fails loudly when the command fails."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr.decode()[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def parse_build(spec):
    """`[NAME=VALUE ...] PATH` -> (path, environment)."""
    words = spec.split()
    env = dict(os.environ)
    for w in words[:-1]:
        k, _, v = w.partition("=")
        env[k] = v
    return os.path.abspath(words[-1]), env


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=9)
    ap.add_argument("--mapc", action="append", required=True)
    ap.add_argument("--work", default=None)
    ap.add_argument("--only", choices=["build", "first"], default=None)
    a = ap.parse_args()
    builds = [parse_build(s) for s in a.mapc]
    if not os.path.isdir(SHARED):
        print("skipped: ../shared not found")
        return
    maps = [os.path.join(SHARED, "maps", m, m + ".building.yaml") for m in MAPS]
    textures = os.path.join(SHARED, "textures")
    cases = []
    if a.only != "first":
        cases.append(("build (7 maps, all targets)",
                      lambda out: ["build", *maps, "-o", out, "--texture-path", textures,
                                   "--quiet"]))
    if a.only != "build":
        for name, src in zip(MAPS, maps):
            cases.append((f"first compile: {name}",
                          lambda out, name=name, src=src: [
                              "gazebo", src, f"{out}/{name}.world", f"{out}/models",
                              "--texture-path", textures, "--quiet"]))
    work = tempfile.mkdtemp(prefix="mapc-compare-", dir=a.work)
    order = random.Random(1)
    print("| case | " + " | ".join(f"wall {k}" for k in range(len(builds)))
          + " | " + " | ".join(f"CPU {k}" for k in range(len(builds)))
          + " | " + " | ".join(f"ratio {k}/0" for k in range(1, len(builds))) + " |")
    print("| --- |" + " ---: |" * (3 * len(builds) - 1))
    try:
        for c, (label, args) in enumerate(cases):
            walls = [[] for _ in builds]
            cpus = [[] for _ in builds]
            for i in range(a.rounds):
                for k in order.sample(range(len(builds)), len(builds)):
                    # Outputs stay until the end: every run makes new files, as a first
                    # build does, and none is freed meanwhile.
                    out = os.path.join(work, f"{c}-{i}-{k}")
                    w, t = timed([builds[k][0], *args(out)], builds[k][1])
                    walls[k].append(w)
                    cpus[k].append(t)
            ms = lambda v: f"{1000 * statistics.median(v):.1f} ms"
            ratios = [statistics.median(w1 / w0 for w0, w1 in zip(walls[0], walls[k]))
                      for k in range(1, len(builds))]
            print(f"| {label} | " + " | ".join(ms(w) for w in walls) + " | "
                  + " | ".join(ms(t) for t in cpus) + " | "
                  + " | ".join(f"{r:.3f}" for r in ratios) + " |", flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for k, (path, _) in enumerate(builds):
        print(f"{k}: {a.mapc[k]}")


if __name__ == "__main__":
    main()
