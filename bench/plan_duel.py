#!/usr/bin/env python3
"""Planning time of a scene spec with one or more fray-cli builds, interleaved.

Runs `fray-cli simulate` REPEAT times per build, alternating the builds, and
reports the median and range of the planning wall clock that simulate prints
("planning: X s wall clock"; project loading excluded), of the CPU time of the
whole process (user + system, all threads, loading included: on a shared
machine the wall clock says more about the other load than about the build)
and whether every build's scene file is the same byte for byte as the first
build's.

  python3 bench/plan_duel.py build/demo-library/demo.frayproj \
      --spec resources/demo/duel.json --cli old=/path/old/fray-cli --cli new=build/bin/fray-cli
"""
import argparse
import filecmp
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("project", help="project file (*.frayproj)")
    ap.add_argument("--spec", required=True, help="scene spec (JSON)")
    ap.add_argument("--cli", action="append", required=True, metavar="NAME=PATH",
                    help="a fray-cli build to time (repeatable; the first is the reference for the scene bytes)")
    ap.add_argument("--repeat", type=int, default=10, help="runs per build (default 10)")
    args = ap.parse_args()
    builds = []
    for item in args.cli:
        name, sep, path = item.partition("=")
        if not sep or not os.path.isfile(path):
            print(f"--cli {item}: expected NAME=PATH to a fray-cli executable", file=sys.stderr)
            return 2
        builds.append((name, path))
    times = {name: [] for name, _ in builds}
    cpu = {name: [] for name, _ in builds}
    with tempfile.TemporaryDirectory() as tmp:
        outs = {name: os.path.join(tmp, f"{name}.frayscene") for name, _ in builds}
        for _ in range(args.repeat):
            for name, path in builds:
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                r = subprocess.run([path, "simulate", args.project, "--spec", args.spec, "--out", outs[name], "--quiet"],
                                   capture_output=True, text=True)
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                if r.returncode != 0:
                    print(f"{name}: simulate failed: {r.stderr.strip()}", file=sys.stderr)
                    return 1
                cpu[name].append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
                m = re.search(r"planning: ([0-9.]+) s wall clock", r.stdout + r.stderr)
                if not m:
                    print(f"{name}: no 'planning:' line in the output", file=sys.stderr)
                    return 1
                times[name].append(float(m.group(1)))
        ref = outs[builds[0][0]]
        for name, _ in builds:
            t = times[name]
            same = "reference" if outs[name] == ref else ("same bytes" if filecmp.cmp(ref, outs[name], shallow=False) else "DIFFERENT bytes")
            c = cpu[name]
            print(f"{name}: median {statistics.median(t):.3f} s, range {min(t):.3f}-{max(t):.3f} s over {len(t)} runs; "
                  f"process CPU median {statistics.median(c):.3f} s, range {min(c):.3f}-{max(c):.3f} s; scene {same}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
