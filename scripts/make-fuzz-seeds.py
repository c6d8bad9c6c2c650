#!/usr/bin/env python3
"""Builds a small libFuzzer seed corpus from the shared captures: each file's
HIERARCHY plus its first three frames (Frames: rewritten to 3), and the
malformed-file corpus. Seeds stay small so the fuzzer explores structure."""
import pathlib
import sys

shared, tests_data, out = map(pathlib.Path, sys.argv[1:4])
out.mkdir(parents=True, exist_ok=True)
n = 0
for f in sorted((shared / "mocap").rglob("*.bvh")):
    text = f.read_bytes().decode("latin-1")
    head, sep, rest = text.partition("MOTION")
    if not sep:
        continue
    lines = rest.splitlines(keepends=True)
    body = [l for l in lines[3:6]]
    seed = head + "MOTION\nFrames: 3\n" + lines[2] + "".join(body)
    (out / f"shared_{f.stem}.bvh").write_bytes(seed.encode("latin-1"))
    n += 1
for f in sorted((tests_data).rglob("*.bvh")):
    if f.stat().st_size <= 16384:
        (out / f"data_{f.parent.name}_{f.name}").write_bytes(f.read_bytes())
        n += 1
print(f"make-fuzz-seeds: {n} seeds in {out}")
