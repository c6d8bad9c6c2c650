#!/usr/bin/env python3
"""Writes crowd_floor.png, the painted area of the 10,000-character domino
demo (domino_crowd.json): 180 x 180 pixels at 1 m a pixel, black (painted) on
white: a large square field with a ring cut out and four round holes, so the
chains have edges to stop at inside the field as well as around it.
Usage: make_crowd_floor.py [OUT.png]"""
import math
import pathlib
import struct
import sys
import zlib

W = H = 180


def painted(x, y):
    cx, cy = x + 0.5 - W / 2, y + 0.5 - H / 2
    if max(abs(cx), abs(cy)) > 86:
        return False  # a white border
    r = math.hypot(cx, cy)
    if 30 < r < 33:
        return False  # a ring path through the field
    for hx, hy in ((-45, -45), (45, -45), (-45, 45), (45, 45)):
        if math.hypot(cx - hx, cy - hy) < 9:
            return False
    return True


def png(rows):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + bytes(0 if painted(x, y) else 255 for x in range(W)) for y in range(rows))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, rows, 8, 0, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).with_name("crowd_floor.png")
out.write_bytes(png(H))
print(f"{out}: {W} x {H} pixels")
