#!/usr/bin/env python3
"""Segmentation timeline of one motion, as in thesis fig. 3.1.

Reads the CSV written by `fray-cli timeline PROJECT MOTION -o FILE.csv` and
draws, over time: (a) the acceleration profile (log scale) with the threshold,
(b) high-acceleration periods, (c) left and right foot contacts, (d) the cuts
(automatic in black, the project's in orange, when they differ).

    python3 scripts/plot_timeline.py FILE.csv -o docs/images/timeline.png
                                     [--first F] [--frames N] [--title TEXT]
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_demo import Image  # noqa: E402  (stdlib-only PNG raster)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--frames", type=int, default=1200)
    ap.add_argument("--title", default="")
    args = ap.parse_args()

    header, rows = "", []
    with open(args.csv) as f:
        for line in f:
            if line.startswith("#"):
                header = line[1:].strip()
            elif line[0].isdigit():
                rows.append([float(x) for x in line.split(",")])
    threshold = float(header.split("threshold")[1].strip()) if "threshold" in header else 0.0
    fps = float(header.split("fps")[1].split(",")[0]) if "fps" in header else 60.0
    rows = rows[args.first:args.first + args.frames]
    if not rows:
        sys.exit("no frames in range")

    w, h = 1400, 420
    left, right = 70, 20
    img = Image(w, h)
    plot_w = w - left - right
    n = len(rows)

    def x_of(i):
        return left + int(i * plot_w / max(1, n - 1))

    # (a) acceleration, log10 scale.
    top, bottom = 40, 220
    lo, hi = 1.0, max(10.0, max(r[1] for r in rows) * 1.2)

    def y_of(v):
        v = max(lo, v)
        return bottom - int((math.log10(v) - math.log10(lo)) / (math.log10(hi) - math.log10(lo)) * (bottom - top))

    # (b) high-acceleration periods as shaded columns behind the curve.
    for i, r in enumerate(rows):
        if r[2] > 0:
            img.rect(x_of(i), top, x_of(i) + 2, bottom, (255, 222, 205))
    img.rect(left, bottom, w - right, bottom + 1, (120, 120, 120))
    if threshold > 0:
        ty = y_of(threshold)
        for x in range(left, w - right, 6):
            img.rect(x, ty, x + 3, ty + 1, (200, 60, 40))
        img.text(w - right - 120, ty - 10, "threshold", (200, 60, 40))
    prev = None
    for i, r in enumerate(rows):
        p = (x_of(i), y_of(r[1]))
        if prev:
            img.line(prev, p, 0.6, (40, 40, 40))
        prev = p
    img.text(8, top, "accel", (40, 40, 40))
    img.text(8, top + 10, "log", (40, 40, 40))

    # (c) contacts.
    for k, (label, color, y0) in enumerate((("left", (60, 110, 220), 245), ("right", (220, 70, 60), 275))):
        img.text(8, y0 + 6, label, color)
        for i, r in enumerate(rows):
            if r[3 + k] > 0:
                img.rect(x_of(i), y0, x_of(i) + 2, y0 + 20, color)
    # Support pattern: double support in green.
    img.text(8, 311, "double", (60, 150, 80))
    for i, r in enumerate(rows):
        if r[3] > 0 and r[4] > 0:
            img.rect(x_of(i), 305, x_of(i) + 2, 325, (60, 150, 80))

    # (d) cuts.
    img.text(8, 346, "cuts", (0, 0, 0))
    for i, r in enumerate(rows):
        if r[5] > 0:
            img.rect(x_of(i), top, x_of(i) + 1, 360, (0, 0, 0))
        if r[6] > 0 and r[5] == 0:
            img.rect(x_of(i), 340, x_of(i) + 2, 372, (240, 150, 20))

    # Time axis (seconds).
    t0 = args.first / fps
    for s in range(int(math.ceil(t0)), int(t0 + n / fps) + 1):
        x = x_of(int(round(s * fps - args.first)))
        img.rect(x, 380, x + 1, 386, (80, 80, 80))
        img.text(x - 6, 392, "%ds" % s, (80, 80, 80))
    title = args.title or header
    img.text(left, 12, title, (20, 20, 20))
    img.text(w - 560, 12, "black: automatic cuts  orange: project cuts", (20, 20, 20))
    img.save(args.out)
    print(args.out)


if __name__ == "__main__":
    main()
