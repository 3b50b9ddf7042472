#!/usr/bin/env python3
"""First compile against the reference (issue 12, BENCHMARKS.md), side by side.

For every demo map, ROUNDS times: the reference `building_map_generator gazebo` (run by
../shared/tools/reference-gen) and `mapc gazebo`, alternately, each into a fresh output
directory (a first build, as in CI). Prints per map the median wall time of each, the
median of the per-round ratios (reference / mapc), and both commands' median CPU time
(user + system, from the children's rusage).

    scripts/first_compile.py [--rounds 9] [--mapc target/release/mapc ...] [--work DIR] [MAP ...]

--mapc may be given several times (an older build beside a newer one): every round then
runs the reference and each build, the builds in a new random order per round, and each
build gets its own row.

--work: where the fresh output directories are made (default: the system's temporary
directory); e.g. /dev/shm to take the file system's inode allocation out of the figures.
Every output stays until the end of the run (about 60 MB for the seven maps at 7 rounds).

Textures: the reference copies them from its share directory; mapc is given the same
directory with --texture-path. Run from the crate root; needs ../shared.
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

from paths import SHARED, release_mapc

MAPS = ["triple_H", "battle_royale", "office", "campus", "hotel", "airport_terminal", "clinic"]


def timed(cmd):
    """(wall seconds, CPU seconds) of one run; fails loudly when the command fails."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr.decode()[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=9)
    ap.add_argument("--mapc", action="append", default=None)
    ap.add_argument("--work", default=None)
    ap.add_argument("maps", nargs="*", default=MAPS)
    a = ap.parse_args()
    builds = a.mapc or [release_mapc()]
    if not os.path.isdir(SHARED):
        print("skipped: ../shared not found")
        return
    ref = os.path.join(SHARED, "tools/reference-gen")
    textures = os.path.join(SHARED, "textures")
    work = tempfile.mkdtemp(prefix="mapc-first-compile-", dir=a.work)
    label = (lambda b: "" if len(builds) == 1 else f" ({b})")
    print(f"| map | reference wall (median) | mapc wall (median) | ratio (median of {a.rounds}) "
          "| min ratio | reference CPU | mapc CPU |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    worst = [None] * len(builds)
    order = random.Random(1)
    try:
        # One untimed reference run first: its venv and Python caches are made once.
        first = os.path.join(SHARED, "maps", a.maps[0], a.maps[0] + ".building.yaml")
        timed([ref, "gazebo", first, os.path.join(work, "w", "x.world"), os.path.join(work, "w", "m")])
        for name in a.maps:
            src = os.path.join(SHARED, "maps", name, name + ".building.yaml")
            rw, rc = [], []
            mw = [[] for _ in builds]
            mc = [[] for _ in builds]
            ratios = [[] for _ in builds]
            for i in range(a.rounds):
                out = os.path.join(work, f"{name}-{i}")
                w, c = timed([ref, "gazebo", src, f"{out}/ref/{name}.world", f"{out}/ref/models"])
                rw.append(w)
                rc.append(c)
                for k in order.sample(range(len(builds)), len(builds)):
                    w2, c2 = timed([builds[k], "gazebo", src, f"{out}/mapc{k}/{name}.world",
                                    f"{out}/mapc{k}/models", "--texture-path", textures, "--quiet"])
                    mw[k].append(w2)
                    mc[k].append(c2)
                    ratios[k].append(w / w2)
                # Outputs stay until the end: on ext4 without a journal, a file created
                # within seconds of a deletion in its block group skips every inode freed
                # then (BENCHMARKS.md), so removing each round's outputs would slow the
                # next round's file creation by the benchmark's own doing.
            ms = lambda v: f"{1000 * statistics.median(v):.1f} ms"
            for k, b in enumerate(builds):
                ratio = statistics.median(ratios[k])
                worst[k] = ratio if worst[k] is None else min(worst[k], ratio)
                print(f"| {name}{label(b)} | {ms(rw)} | {ms(mw[k])} | **{ratio:.0f}x** "
                      f"| {min(ratios[k]):.0f}x | {ms(rc)} | {ms(mc[k])} |", flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for k, b in enumerate(builds):
        print(f"\nworst median ratio{label(b)}: {worst[k]:.0f}x (target 50x)")


if __name__ == "__main__":
    main()
