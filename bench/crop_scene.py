#!/usr/bin/env python3
"""Writes a part of a large scene file as a scene of its own, for `fray-cli metrics`.

The metrics compare every pair of characters at every frame, too slow for a
10,000-character scene; a part of it is measured instead (docs/BENCHMARKS.md,
"Composition at scale, fifth pass"). The part is either every K-th group of a
scene made of groups named "GROUP-N/..." (one-vs-many fights "fight-N/", football
runs "run-N/"): the groups 1, 1 + K, 1 + 2K, ... whole (or from 1 + OFFSET); or the characters whose
first instance's root lies in floor windows (x0 z0 x1 z1, metres), as the
tests' cropScene does (the root of a first instance that starts at clip time 0,
where every clip's root is the identity). As tests/sim/scene_crop.h: hits
between two kept characters are kept (indices renumbered), opponents are
cleared, a ball whose holder is left out is nobody's. The project path is made
absolute so the part opens from anywhere.

    crop_scene.py IN.frayscene OUT.frayscene --every 50 [--group fight]
    crop_scene.py IN.frayscene OUT.frayscene --window -60 -60 -52 -52 --window 20 -50 28 -42
"""
import argparse
import json
import os
import re
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--every", type=int, help="keep the groups 1, 1 + K, 1 + 2K, ... (names GROUP-N/...)")
    ap.add_argument("--offset", type=int, default=0, help="with --every: the groups 1 + OFFSET, 1 + OFFSET + K, ...")
    ap.add_argument("--all-offsets", action="store_true",
                    help="with --every: K parts from one reading, OUT with the offset before its extension (part-0.frayscene ...)")
    ap.add_argument("--group", default=None, help="the groups' name (fight, run); default: any NAME-N/ prefix")
    ap.add_argument("--window", type=float, nargs=4, action="append", metavar=("X0", "Z0", "X1", "Z1"))
    args = ap.parse_args()
    if (args.every is None) == (args.window is None):
        sys.exit("crop_scene.py: give --every K or --window X0 Z0 X1 Z1 (one of them)")
    with open(args.scene) as f:
        scene = json.load(f)
    if scene.get("format") != "fray-scene":
        sys.exit(f"crop_scene.py: {args.scene}: not a Fray scene (format {scene.get('format')!r})")
    group = re.compile(r"^(%s)-(\d+)/" % (re.escape(args.group) if args.group else r"[A-Za-z_]+"))

    characters, all_hits = scene["characters"], scene.get("hits", [])

    def write(offset, out):
        def keep(c):
            if args.every is not None:
                m = group.match(c["name"])
                return bool(m) and (int(m.group(2)) - 1) % args.every == offset
            if not c.get("track"):
                return False  # creatures: keyed, not cropped
            x, z = c["track"][0]["root"][0], c["track"][0]["root"][1]
            return any(x0 <= x <= x1 and z0 <= z <= z1 for x0, z0, x1, z1 in args.window)

        total = len(characters)
        index, kept = {}, []
        for n, c in enumerate(characters):
            if keep(c):
                index[n] = len(kept)
                kept.append(dict(c))  # parts share the scene read once
        for c in kept:
            c["opponent"] = -1
            if "holder" in c and c["holder"] >= 0:
                c["holder"] = index.get(c["holder"], -1)
        hits = []
        for h in all_hits:
            if h["attacker"] in index and h["defender"] in index:
                h = dict(h, attacker=index[h["attacker"]], defender=index[h["defender"]])
                hits.append(h)
        project = scene["project"]
        if not os.path.isabs(project):
            here = os.path.join(os.path.dirname(os.path.abspath(args.scene)), project)
            project = os.path.abspath(project if os.path.exists(project) else here)
        part = dict(scene, project=project, characters=kept, hits=hits)
        part["catches"] = []
        with open(out, "w") as f:
            json.dump(part, f, indent=1)
        print(f"{out}: {len(kept)} of {total} characters kept, {len(hits)} hits")

    if args.all_offsets:
        stem, ext = os.path.splitext(args.out)
        for offset in range(args.every):
            write(offset, f"{stem}-{offset}{ext}")
    else:
        write(args.offset, args.out)


if __name__ == "__main__":
    main()
