#!/usr/bin/env python3
"""Compares a scene written with looped idles (scene version 2) with the same scene
written before they existed (version 1, one instance a time round).

Usage: scripts/compare-looped-scene.py OLD.frayscene NEW.frayscene

Every looped instance of NEW ({"loop": L}) is expanded into its repetitions
(repetition k from start + k * L, each from the clip's offset, the last cut at
the instance's end); the two documents must then be equal, field for field,
except the version and the times of the repetitions' seams, which may differ
in the last bits (the old composer summed the clip's duration, the new one
multiplies: at most 1e-9 s apart). Exits 1 naming the first difference.
"""
import json
import math
import sys


def expand(track):
    out = []
    for inst in track:
        loop = inst.pop("loop", None)
        if not loop:
            out.append(inst)
            continue
        start, end = inst["start"], inst["end"]
        n = max(1, math.ceil((end - start) / loop - 1e-6))
        for k in range(n):
            rep = dict(inst)
            rep["start"] = start + k * loop
            rep["end"] = min(end, start + (k + 1) * loop)
            out.append(rep)
    return out


def compare(a, b, path, tol):
    if isinstance(a, dict) and isinstance(b, dict):
        if list(a.keys()) != list(b.keys()):
            return f"{path}: fields {list(a.keys())} vs {list(b.keys())}"
        for k in a:
            d = compare(a[k], b[k], f"{path}/{k}", tol)
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return f"{path}: {len(a)} vs {len(b)} entries"
        for i, (x, y) in enumerate(zip(a, b)):
            d = compare(x, y, f"{path}/{i}", tol)
            if d:
                return d
        return None
    if isinstance(a, float) or isinstance(b, float):
        if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
            return f"{path}: {a!r} vs {b!r}"
        if a != b and abs(a - b) > tol:
            return f"{path}: {a!r} vs {b!r}"
        return None
    return None if a == b else f"{path}: {a!r} vs {b!r}"


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    old = json.load(open(sys.argv[1]))
    new = json.load(open(sys.argv[2]))
    loops = sum(1 for c in new["characters"] for i in c["track"] if "loop" in i)
    instances_old = sum(len(c["track"]) for c in old["characters"])
    instances_new = sum(len(c["track"]) for c in new["characters"])
    for c in new["characters"]:
        c["track"] = expand(c["track"])
    if old.get("version") != 1 or new.get("version") != (2 if loops else 1):
        print(f"versions: old {old.get('version')}, new {new.get('version')} ({loops} looped instances)")
        return 1
    old["version"] = new["version"]
    exact = compare(old, new, "", 0.0)
    diff = compare(old, new, "", 1e-9)
    print(f"{sys.argv[2]}: {instances_new} instances ({loops} looped) against {instances_old}; "
          f"expanded: {'identical' if not exact else 'equal within 1e-9 s (first inexact: ' + exact + ')' if not diff else 'DIFFERENT: ' + diff}")
    return 1 if diff else 0


if __name__ == "__main__":
    sys.exit(main())
