#!/usr/bin/env python3
"""A first compile's wall time after different work just before it (BENCHMARKS.md, part 5).

The first-compile ratio (scripts/first_compile.py) runs mapc right after the reference
generator; this shows how much of mapc's time depends on what ran just before. Each round
runs, in turn, one of these for about 0.45 s and then `mapc gazebo MAP` into a fresh
directory:

- idle: nothing (a sleep);
- spin: a Python process keeping one CPU busy;
- memory: a Python process touching 300 MB;
- writer: a Python process writing 80 files of 40 KB without syncing them;
- reference: the reference generator on the same map (../shared/tools/reference-gen).

    scripts/after_other_work.py [--rounds 11] [--mapc target/release/mapc] [--work DIR] [MAP]

Prints the median wall time of mapc after each. Outputs stay in --work until the end (a
fresh directory of the system's temporary directory by default). Needs ../shared.
"""

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from paths import SHARED, release_mapc


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=11)
    ap.add_argument("--mapc", default=release_mapc())
    ap.add_argument("--work", default=None)
    ap.add_argument("map", nargs="?", default="hotel")
    a = ap.parse_args()
    if not os.path.isdir(SHARED):
        print("skipped: ../shared not found")
        return
    src = os.path.join(SHARED, "maps", a.map, a.map + ".building.yaml")
    work = tempfile.mkdtemp(prefix="mapc-after-", dir=a.work)
    py = sys.executable

    def before(kind, k):
        if kind == "idle":
            time.sleep(0.45)
        elif kind == "spin":
            subprocess.run([py, "-c", "import time\nt=time.time()\nwhile time.time()-t<0.45: pass"])
        elif kind == "memory":
            subprocess.run([py, "-c", "x=bytearray(300<<20)\nfor i in range(0,len(x),4096): x[i]=1"])
        elif kind == "writer":
            d = os.path.join(work, f"writer-{k}")
            subprocess.run([py, "-c", f"import os\nos.makedirs({d!r})\n"
                            f"for i in range(80): open(os.path.join({d!r}, str(i)),'wb').write(os.urandom(40000))"])
        else:
            out = os.path.join(work, f"ref-{k}")
            subprocess.run([os.path.join(SHARED, "tools/reference-gen"), "gazebo", src,
                            f"{out}/x.world", f"{out}/models"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)

    kinds = ["idle", "spin", "memory", "writer", "reference"]
    walls = {k: [] for k in kinds}
    n = 0
    try:
        for _ in range(a.rounds):
            for kind in kinds:
                n += 1
                before(kind, n)
                out = os.path.join(work, f"mapc-{n}")
                start = time.perf_counter()
                r = subprocess.run([a.mapc, "gazebo", src, f"{out}/{a.map}.world", f"{out}/models",
                                    "--texture-path", os.path.join(SHARED, "textures"), "--quiet"],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
                walls[kind].append(time.perf_counter() - start)
                if r.returncode != 0:
                    sys.exit(f"mapc failed ({r.returncode}):\n{r.stderr.decode()[-2000:]}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for kind in kinds:
        print(f"after {kind:9s} {1000 * statistics.median(walls[kind]):.2f} ms")


if __name__ == "__main__":
    main()
