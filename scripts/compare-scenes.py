#!/usr/bin/env python3
"""Plans the same scenes with two fray-cli builds and compares the outputs byte for byte.

Usage: scripts/compare-scenes.py BASE_CLI NEW_CLI [--work DIR] [--keep]

Covers the README demo (scripts/run-demo.sh: the duel, the chase, the demo
patch library, one-vs-many, domino, the football library's patches and run,
the rat) from resources/demo/*.json, and the compose scenes the tests plan
(tests/sim/test_patches.cpp) written here as specs: one-vs-one, luggage with
several seeds, a small rat crowd, domino with other seeds, each spec kind
with the smaller settings of the test that plans every kind. The demo libraries
are generated once, by BASE_CLI, and both builds plan from the same files.

What is compared: every .frayscene and .patches file, byte for byte (a
version-3 .patches file ends with the generation's wall-clock seconds, a
double: those last 8 bytes are left out; with --library-format-changed, the
two builds write different library file versions, so each library is compared
through its own build's `patches list --json` instead), and the text each
command prints with its wall-clock times ("; 1.234 s", "8.67 s wall clock (2.3x
real time)") and the output folder removed.
Exits 1 and names the first bytes that differ when anything does.
"""
import argparse
import json
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEMO = ROOT / "resources" / "demo"


def with_fields(name, spec, **fields):
    out = dict(spec)
    out.update(fields)
    return name, out


def extra_specs():
    """The compose scenes the tests plan, as spec JSON (name, spec, needs the football library)."""
    rat = json.loads((DEMO / "rat.json").read_text())
    specs = [
        ("one_vs_one", {"kind": "one-vs-one", "duration": 40, "seed": 1}, False),
        ("one_vs_one_short", {"kind": "one-vs-one", "duration": 10, "seed": 3}, False),
        ("one_vs_many_3", {"kind": "one-vs-many", "enemies": 3, "duration": 60, "seed": 2}, False),
        ("one_vs_many_10", {"kind": "one-vs-many", "enemies": 10, "duration": 120, "seed": 1}, False),
        ("rat_small", {"kind": "rat", "rat": {"path": [[-3, 0], [3, 0.5]]}, "crowd": 12, "reach": 0.6, "seed": 1}, False),
        ("rat_seed2", dict(rat, seed=2), False),
    ]
    for seed in (1, 2, 3):
        specs.append((f"luggage_{seed}", {"kind": "luggage", "seed": seed, "porters": 4, "handoffs": 9, "duration": 300}, False))
    specs.append(("luggage_small", {"kind": "luggage", "seed": 1, "porters": 3, "handoffs": 2, "duration": 100}, False))
    domino = json.loads((DEMO / "domino.json").read_text())
    domino["floor"]["bitmap"] = str(DEMO / domino["floor"]["bitmap"])
    for seed in (2, 4):
        specs.append((f"domino_{seed}", dict(domino, seed=seed), False))
    football = json.loads((DEMO / "football.json").read_text())
    specs.append(("football_seed2", dict(football, seed=2), True))
    specs.append(("football_singles", dict(football, seed=3, doubles=False, tacklers=5), True))
    return specs


TIME = re.compile(r"(; |, )?[0-9]+\.[0-9]+ s(\n|$)|[0-9.]+ s wall clock \([0-9.]+x real time\)")


def run(cmd, log):
    proc = subprocess.run([str(c) for c in cmd], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({proc.returncode}):\n{proc.stderr}")
    log.append(TIME.sub(lambda m: m.group(2) or "", proc.stdout))


def plan_all(cli, out, lib, football_lib, specs_dir):
    out.mkdir(parents=True, exist_ok=True)
    log = []
    proj = lib / "demo.frayproj"
    fproj = football_lib / "demo.frayproj"
    for name in ("duel", "chase"):
        run([cli, "simulate", proj, "--spec", DEMO / f"{name}.json", "--out", out / f"{name}.frayscene", "--quiet"], log)
    run([cli, "patches", "generate", proj, "--out", out / "demo.patches", "--quiet"], log)
    run([cli, "patches", "generate", fproj, "--out", out / "football.patches", "--quiet"], log)
    demo = [("one_vs_many", DEMO / "one_vs_many.json", False), ("domino", DEMO / "domino.json", False),
            ("football", DEMO / "football.json", True), ("rat", DEMO / "rat.json", False)]
    demo += [(n, specs_dir / f"{n}.json", fb) for n, _, fb in extra_specs()]
    for name, spec, fb in demo:
        project, patches = (fproj, out / "football.patches") if fb else (proj, out / "demo.patches")
        run([cli, "compose", project, "--patches", patches, "--spec", spec, "--out", out / f"{name}.frayscene", "--quiet"], log)
    (out / "stdout.txt").write_text("".join(log).replace(str(out), "OUT"))
    return [p.name for p in sorted(out.iterdir())]


def first_difference(a, b):
    for i, (x, y) in enumerate(zip(a, b)):
        if x != y:
            return i
    return min(len(a), len(b))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("base")
    ap.add_argument("new")
    ap.add_argument("--work", help="folder for the libraries and outputs (default: a temporary one)")
    ap.add_argument("--keep", action="store_true", help="keep the temporary folder")
    ap.add_argument("--reuse-base", action="store_true", help="with --work: keep BASE_CLI's outputs from an earlier run there")
    ap.add_argument("--library-format-changed", action="store_true",
                    help="compare the .patches files through each build's `patches list --json`, not byte for byte")
    args = ap.parse_args()
    work = pathlib.Path(args.work or tempfile.mkdtemp(prefix="fray-compare-"))
    work.mkdir(parents=True, exist_ok=True)
    lib, football_lib, specs_dir = work / "demo-library", work / "football-library", work / "specs"
    specs_dir.mkdir(exist_ok=True)
    for name, spec, _ in extra_specs():
        (specs_dir / f"{name}.json").write_text(json.dumps(spec))
    if not (lib / "demo.frayproj").exists():
        run([args.base, "demo-library", lib], [])
    if not (football_lib / "demo.frayproj").exists():
        run([args.base, "demo-library", football_lib, "--set", "football"], [])
    if args.reuse_base and (work / "base" / "stdout.txt").exists():
        base_files = [p.name for p in sorted((work / "base").iterdir())]
    else:
        base_files = plan_all(pathlib.Path(args.base).resolve(), work / "base", lib, football_lib, specs_dir)
    new_files = plan_all(pathlib.Path(args.new).resolve(), work / "new", lib, football_lib, specs_dir)
    bad = 0
    if base_files != new_files:
        print(f"different outputs: {sorted(set(base_files) ^ set(new_files))}")
        bad += 1
    for name in base_files:
        a, b = (work / "base" / name).read_bytes(), (work / "new" / name).read_bytes()
        if name.endswith(".patches") and args.library_format_changed:
            project = (football_lib if name.startswith("football") else lib) / "demo.frayproj"
            listed = []
            for cli, side in ((args.base, "base"), (args.new, "new")):
                proc = subprocess.run([cli, "patches", "list", str(project), "--out", str(work / side / name), "--json", "-q"],
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE)
                if proc.returncode != 0:
                    sys.exit(f"{cli} patches list {name} failed:\n{proc.stderr.decode()}")
                listed.append(proc.stdout)
            a, b = listed
            name += " (listed)"
        elif name.endswith(".patches"):
            a, b = a[:-8], b[:-8]  # the generation's wall-clock seconds
        if a == b:
            print(f"same      {name} ({len(a)} bytes)")
        else:
            print(f"DIFFERENT {name}: {len(a)} vs {len(b)} bytes, first difference at byte {first_difference(a, b)}")
            bad += 1
    print(f"{len(base_files) - bad} of {len(base_files)} outputs identical" + (f"; outputs in {work}" if bad or args.keep else ""))
    if not bad and not args.keep and not args.work:
        shutil.rmtree(work)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
