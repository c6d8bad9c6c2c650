#!/usr/bin/env python3
"""Stick-figure contact sheet of demo-actor actions.

Reads the BVH takes and ground-truth JSON written by
`fray-cli demo-library OUTDIR` and draws, for each chosen action kind, a row of
poses spread over the action (first instance found in the library). Left limbs
are blue, right limbs red; a foot in ground-truth contact is drawn green.
Only the Python standard library is used (zlib writes the PNG).

    python3 scripts/plot_demo.py OUTDIR [-o docs/images/demo_contact_sheet.png]
                                        [--actions jab,cross,...] [--columns 6]
                                        [--take NAME --frames A:B:STEP]
"""
import argparse
import json
import math
import os
import struct
import zlib

# ---- BVH -------------------------------------------------------------------------


def read_bvh(path):
    with open(path) as f:
        tokens = f.read().split()
    i = 0
    names, parents, offsets, channels = [], [], [], []
    stack = []
    end_sites = {}
    while tokens[i] != "MOTION":
        t = tokens[i]
        if t in ("ROOT", "JOINT"):
            names.append(tokens[i + 1])
            parents.append(stack[-1] if stack else -1)
            offsets.append(None)
            channels.append([])
            stack.append(len(names) - 1)
            i += 3  # name and "{"
        elif t == "End":
            j = tokens.index("OFFSET", i)
            end_sites[stack[-1]] = tuple(float(x) for x in tokens[j + 1:j + 4])
            i = tokens.index("}", j) + 1
        elif t == "OFFSET":
            offsets[stack[-1]] = tuple(float(x) for x in tokens[i + 1:i + 4])
            i += 4
        elif t == "CHANNELS":
            n = int(tokens[i + 1])
            channels[stack[-1]] = tokens[i + 2:i + 2 + n]
            i += 2 + n
        elif t == "}":
            stack.pop()
            i += 1
        else:
            i += 1
    frames = int(tokens[i + 2])
    frame_time = float(tokens[i + 5])
    values = [float(x) for x in tokens[i + 6:]]
    per = sum(len(c) for c in channels)
    rows = [values[f * per:(f + 1) * per] for f in range(frames)]
    return {"names": names, "parents": parents, "offsets": offsets, "channels": channels,
            "end_sites": end_sites, "rows": rows, "fps": 1.0 / frame_time}


def axis_matrix(axis, deg):
    a = math.radians(deg)
    c, s = math.cos(a), math.sin(a)
    if axis == "X":
        return ((1, 0, 0), (0, c, -s), (0, s, c))
    if axis == "Y":
        return ((c, 0, s), (0, 1, 0), (-s, 0, c))
    return ((c, -s, 0), (s, c, 0), (0, 0, 1))


def mat_mul(a, b):
    return tuple(tuple(sum(a[r][k] * b[k][c] for k in range(3)) for c in range(3)) for r in range(3))


def mat_vec(m, v):
    return tuple(m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2] for r in range(3))


def pose(bvh, frame, rotations=None):
    """World positions of the joints and of the end sites (by joint index)."""
    row = bvh["rows"][frame]
    k = 0
    world_r, world_p = {}, {}
    ends = {}
    for j, name in enumerate(bvh["names"]):
        pos = list(bvh["offsets"][j])
        rot = ((1, 0, 0), (0, 1, 0), (0, 0, 1))
        for ch in bvh["channels"][j]:
            v = row[k]
            k += 1
            if ch.endswith("position"):
                pos["XYZ".index(ch[0])] = v
            else:
                rot = mat_mul(rot, axis_matrix(ch[0], v))
        p = bvh["parents"][j]
        if p < 0:
            world_p[j] = tuple(pos)
            world_r[j] = rot
        else:
            off = mat_vec(world_r[p], pos)
            world_p[j] = tuple(world_p[p][i] + off[i] for i in range(3))
            world_r[j] = mat_mul(world_r[p], rot)
        if j in bvh["end_sites"]:
            off = mat_vec(world_r[j], bvh["end_sites"][j])
            ends[j] = tuple(world_p[j][i] + off[i] for i in range(3))
    if rotations is not None:
        rotations.update(world_r)
    return world_p, ends


# ---- raster ----------------------------------------------------------------------


class Image:
    def __init__(self, w, h, bg=(250, 250, 247)):
        self.w, self.h = w, h
        self.px = bytearray(bytes(bg) * (w * h))

    def dot(self, x, y, r, color):
        x0, x1 = int(x - r), int(x + r) + 1
        y0, y1 = int(y - r), int(y + r) + 1
        rr = r * r
        for yy in range(max(0, y0), min(self.h, y1)):
            dy = yy - y
            for xx in range(max(0, x0), min(self.w, x1)):
                dx = xx - x
                if dx * dx + dy * dy <= rr:
                    o = 3 * (yy * self.w + xx)
                    self.px[o:o + 3] = bytes(color)

    def line(self, a, b, r, color):
        n = max(1, int(math.hypot(b[0] - a[0], b[1] - a[1])))
        for i in range(n + 1):
            t = i / n
            self.dot(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, r, color)

    def rect(self, x0, y0, x1, y1, color):
        for y in range(max(0, y0), min(self.h, y1)):
            o = 3 * (y * self.w + max(0, x0))
            self.px[o:o + 3 * (min(self.w, x1) - max(0, x0))] = bytes(color) * (min(self.w, x1) - max(0, x0))

    def text(self, x, y, s, color, scale=1):
        for ch in s.lower():
            glyph = FONT.get(ch, FONT["?"])
            for r, bits in enumerate(glyph):
                for c in range(5):
                    if bits & (1 << (4 - c)):
                        self.rect(x + c * scale, y + r * scale, x + (c + 1) * scale, y + (r + 1) * scale, color)
            x += 6 * scale

    def save(self, path):
        raw = b"".join(b"\x00" + bytes(self.px[3 * y * self.w:3 * (y + 1) * self.w]) for y in range(self.h))

        def chunk(tag, data):
            c = struct.pack(">I", len(data)) + tag + data
            return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

        png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", self.w, self.h, 8, 2, 0, 0, 0))
        png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
        with open(path, "wb") as f:
            f.write(png)


# 5x7 glyphs, one int per row (5 bits).
FONT = {
    "a": [0, 0, 14, 1, 15, 17, 15], "b": [16, 16, 22, 25, 17, 17, 30], "c": [0, 0, 14, 16, 16, 17, 14],
    "d": [1, 1, 13, 19, 17, 17, 15], "e": [0, 0, 14, 17, 31, 16, 14], "f": [6, 9, 8, 28, 8, 8, 8],
    "g": [0, 15, 17, 17, 15, 1, 14], "h": [16, 16, 22, 25, 17, 17, 17], "i": [4, 0, 12, 4, 4, 4, 14],
    "j": [2, 0, 6, 2, 2, 18, 12], "k": [16, 16, 18, 20, 24, 20, 18], "l": [12, 4, 4, 4, 4, 4, 14],
    "m": [0, 0, 26, 21, 21, 17, 17], "n": [0, 0, 22, 25, 17, 17, 17], "o": [0, 0, 14, 17, 17, 17, 14],
    "p": [0, 0, 30, 17, 30, 16, 16], "q": [0, 0, 13, 19, 15, 1, 1], "r": [0, 0, 22, 25, 16, 16, 16],
    "s": [0, 0, 14, 16, 14, 1, 30], "t": [8, 8, 28, 8, 8, 9, 6], "u": [0, 0, 17, 17, 17, 19, 13],
    "v": [0, 0, 17, 17, 17, 10, 4], "w": [0, 0, 17, 17, 21, 21, 10], "x": [0, 0, 17, 10, 4, 10, 17],
    "y": [0, 0, 17, 17, 15, 1, 14], "z": [0, 0, 31, 2, 4, 8, 31], "_": [0, 0, 0, 0, 0, 0, 31],
    " ": [0] * 7, "-": [0, 0, 0, 31, 0, 0, 0], ".": [0, 0, 0, 0, 0, 12, 12], ":": [0, 12, 12, 0, 12, 12, 0],
    "(": [2, 4, 8, 8, 8, 4, 2], ",": [0, 0, 0, 0, 12, 4, 8], ")": [8, 4, 2, 2, 2, 4, 8], "/": [1, 1, 2, 4, 8, 16, 16],
    "0": [14, 17, 19, 21, 25, 17, 14], "1": [4, 12, 4, 4, 4, 4, 14], "2": [14, 17, 1, 2, 4, 8, 31],
    "3": [31, 2, 4, 2, 1, 17, 14], "4": [2, 6, 10, 18, 31, 2, 2], "5": [31, 16, 30, 1, 1, 17, 14],
    "6": [6, 8, 16, 30, 17, 17, 14], "7": [31, 1, 2, 4, 8, 8, 8], "8": [14, 17, 17, 14, 17, 17, 14],
    "9": [14, 17, 17, 15, 1, 2, 12], "?": [14, 17, 1, 2, 4, 0, 4],
}

# ---- drawing ---------------------------------------------------------------------

LEFT, RIGHT, MID, GREEN = (40, 90, 200), (200, 50, 50), (60, 60, 60), (20, 160, 60)


VIEW = math.radians(60)


def project(p, origin, yaw, scale, cx, cy):
    """Orthographic view from the actor's front-left (VIEW off the facing), Y up."""
    x, y, z = p[0] - origin[0], p[1], p[2] - origin[2]
    c, s = math.cos(-yaw), math.sin(-yaw)
    x, z = c * x + s * z, -s * x + c * z  # into the actor's heading frame (x left, z forward)
    u = math.cos(VIEW) * x - math.sin(VIEW) * z
    depth = math.sin(VIEW) * x + math.cos(VIEW) * z
    return (cx - u * scale, cy - (y + 0.12 * depth) * scale)


def heading_of(bvh, frame):
    """Facing of the head on the floor (the actor looks at the opponent), else of the hips."""
    names = bvh["names"]
    rots = {}
    world, _ = pose(bvh, frame, rots)
    fwd = mat_vec(rots[names.index("Head")], (0, 0, 1))
    if math.hypot(fwd[0], fwd[2]) > 0.4:
        return math.atan2(fwd[0], fwd[2])
    l, r = world[names.index("LeftUpLeg")], world[names.index("RightUpLeg")]
    return math.atan2(-(l[2] - r[2]), l[0] - r[0])


def draw_pose(img, bvh, frame, truth, x0, y0, w, h, yaw, origin, scale):
    names = bvh["names"]
    world, ends = pose(bvh, frame)
    cx, cy = x0 + w / 2, y0 + h - 14
    # floor grid around the origin
    for gx in range(-3, 4):
        for gz in range(-3, 4):
            q = project((origin[0] + gx * 0.5, 0, origin[2] + gz * 0.5), origin, yaw, scale, cx, cy)
            if x0 < q[0] < x0 + w and y0 < q[1] < y0 + h:
                img.dot(q[0], q[1], 1.2, (190, 190, 185))
    contact = {"Left": truth["foot_contact"]["left"][frame], "Right": truth["foot_contact"]["right"][frame]}

    def color(name):
        if name.startswith("Left"):
            return GREEN if name in ("LeftFoot", "LeftToe") and contact["Left"] else LEFT
        if name.startswith("Right"):
            return GREEN if name in ("RightFoot", "RightToe") and contact["Right"] else RIGHT
        return MID

    segs = []
    for j, p in enumerate(bvh["parents"]):
        if p >= 0:
            segs.append((world[p], world[j], color(names[j])))
        if j in ends:
            segs.append((world[j], ends[j], color(names[j])))
    # far side first
    def depth(seg):
        m = [(seg[0][i] + seg[1][i]) / 2 for i in range(3)]
        return project(m, origin, yaw, 1, 0, 0)[1]
    for a, b, col in sorted(segs, key=lambda s: -sum(s[0]) - sum(s[1])):
        img.line(project(a, origin, yaw, scale, cx, cy), project(b, origin, yaw, scale, cx, cy), 1.6, col)
    head = ends.get(names.index("Head"), world[names.index("Head")])
    hc = [(world[names.index("Head")][i] + head[i]) / 2 for i in range(3)]
    q = project(hc, origin, yaw, scale, cx, cy)
    img.dot(q[0], q[1], 0.11 * scale, MID)
    img.dot(q[0], q[1], 0.11 * scale - 2, (250, 250, 247))


def load_library(folder):
    takes = {}
    for fn in sorted(os.listdir(folder)):
        if fn.endswith(".truth.json"):
            with open(os.path.join(folder, fn)) as f:
                truth = json.load(f)
            takes[truth["take"]] = (os.path.join(folder, truth["motion"]), truth)
    return takes


DEFAULT_ACTIONS = ["jab", "cross", "hook_left", "uppercut_right", "front_kick", "roundhouse_right", "knee_strike",
                   "block_high", "slip_left", "duck", "sway_back", "pivot_left", "head_snap", "knocked_down",
                   "fall_forward", "fall_backward", "fall_sideways", "get_up", "walk", "run", "backpedal",
                   "pick_up_box", "walk_carry", "hand_over"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("library", help="folder written by fray-cli demo-library")
    ap.add_argument("-o", "--output", default="docs/images/demo_contact_sheet.png")
    ap.add_argument("--actions", default=",".join(DEFAULT_ACTIONS))
    ap.add_argument("--columns", type=int, default=6)
    ap.add_argument("--instance", type=int, default=0, help="which occurrence of each action")
    ap.add_argument("--take", help="draw frames of one take instead of actions")
    ap.add_argument("--frames", default="0:60:10", help="A:B:STEP with --take")
    ap.add_argument("--cell", type=int, default=150, help="panel width in pixels")
    ap.add_argument("--view", type=float, default=60.0, help="camera angle off the actor's facing (degrees)")
    ap.add_argument("--blocks", type=int, default=2, help="side-by-side blocks of action rows")
    args = ap.parse_args()
    global VIEW
    VIEW = math.radians(args.view)

    takes = load_library(args.library)
    bvh_cache = {}

    def bvh_of(name):
        if name not in bvh_cache:
            bvh_cache[name] = read_bvh(takes[name][0])
        return bvh_cache[name]

    rows = []  # (label, take, [frames])
    if args.take:
        a, b, s = (int(x) for x in args.frames.split(":"))
        frames = list(range(a, b + 1, s))
        for i in range(0, len(frames), args.columns):
            rows.append(("%s %d" % (args.take, frames[i]), args.take, frames[i:i + args.columns]))
    else:
        for name in args.actions.split(","):
            found = [(t, a) for t, (_, truth) in takes.items() for a in truth["actions"] if a["name"] == name]
            if not found:
                print("no action", name)
                continue
            take, act = found[min(args.instance, len(found) - 1)]
            f0, f1 = act["first_frame"], act["last_frame"]
            n = args.columns
            frames = [round(f0 + (f1 - f0) * i / (n - 1)) for i in range(n)]
            label = "%s (%s, %.2f s)" % (name, act["style"], (f1 - f0 + 1) / takes[take][1]["fps"])
            rows.append((label, take, frames))

    cw, ch, label_h, gap = args.cell, int(args.cell * 1.25), 14, 12
    blocks = max(1, min(args.blocks, len(rows)))
    per_block = (len(rows) + blocks - 1) // blocks
    block_w = cw * args.columns
    img = Image(blocks * block_w + (blocks - 1) * gap, per_block * (ch + label_h))
    img.rect(0, 0, img.w, img.h, (250, 250, 247))
    for b in range(1, blocks):
        img.rect(b * (block_w + gap) - gap, 0, b * (block_w + gap), img.h, (205, 205, 200))
    scale = ch / 2.3
    for r, (label, take, frames) in enumerate(rows):
        bvh, truth = bvh_of(take), takes[take][1]
        x0 = (r // per_block) * (block_w + gap)
        y0 = (r % per_block) * (ch + label_h)
        img.rect(x0, y0, x0 + block_w, y0 + label_h, (232, 232, 226))
        img.text(x0 + 4, y0 + 3, label, (30, 30, 30))
        yaw = heading_of(bvh, frames[0])
        for c, f in enumerate(frames):
            world, _ = pose(bvh, f)
            draw_pose(img, bvh, f, truth, x0 + c * cw, y0 + label_h, cw, ch, yaw, (world[0][0], 0, world[0][2]), scale)
            img.text(x0 + c * cw + 3, y0 + label_h + 3, "f%d" % f, (140, 140, 140))
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    img.save(args.output)
    print("wrote", args.output, "(%dx%d)" % (img.w, img.h))


if __name__ == "__main__":
    main()
