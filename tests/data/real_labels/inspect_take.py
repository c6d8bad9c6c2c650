#!/usr/bin/env python3
"""Signals for labelling a real take by hand (pure Python, no numpy).

Input: a BVH in metres, Y up (`fray-cli convert CAPTURE out.bvh`). Output: a
per-frame CSV of the signals the labels were read from, and a PNG strip plot
(time on x; one panel per signal) to look at with an image viewer.

  python3 inspect_take.py take.bvh --csv take.csv --png take.png [--from S --to S]

Signals (body height H = standing head height, 90th percentile):
  pelvis_h     pelvis height above the take's floor (2nd percentile of the feet), in H
  lhand, rhand hand speed relative to the pelvis, H/s
  lfoot, rfoot ankle speed relative to the pelvis, H/s
  lfh, rfh     lower of ankle/toe height above its own floor level, m
  lfs, rfs     slower of ankle/toe world speed, m/s
"""
import argparse, math, struct, zlib

def parse_bvh(path):
    toks = open(path).read().split()
    i = 0
    joints = []  # name, parent, offset, channels
    stack = []
    while toks[i] != 'MOTION':
        t = toks[i]
        if t in ('ROOT', 'JOINT'):
            joints.append([toks[i + 1], stack[-1] if stack else -1, None, []])
            cur = len(joints) - 1
            i += 2
        elif t == 'End':
            joints.append(['_end', stack[-1], None, []])
            cur = len(joints) - 1
            i += 2
        elif t == '{':
            stack.append(cur); i += 1
        elif t == '}':
            stack.pop(); i += 1
        elif t == 'OFFSET':
            joints[cur][2] = [float(x) for x in toks[i + 1:i + 4]]; i += 4
        elif t == 'CHANNELS':
            n = int(toks[i + 1]); joints[cur][3] = toks[i + 2:i + 2 + n]; i += 2 + n
        else:
            i += 1
    nframes = int(toks[i + 2]); dt = float(toks[i + 5]); i += 6
    nch = sum(len(j[3]) for j in joints)
    data = [[float(x) for x in toks[i + k * nch:i + (k + 1) * nch]] for k in range(nframes)]
    return joints, data, 1.0 / dt

def rot(axis, deg):
    a = math.radians(deg); c, s = math.cos(a), math.sin(a)
    if axis == 'X': return [[1, 0, 0], [0, c, -s], [0, s, c]]
    if axis == 'Y': return [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]

def mm(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(3)) for c in range(3)] for r in range(3)]

def mv(a, v):
    return [sum(a[r][k] * v[k] for k in range(3)) for r in range(3)]

def world(joints, data):
    out = []
    for row in data:
        k = 0; R = []; P = []
        for name, parent, off, ch in joints:
            pos = list(off); m = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
            for c in ch:
                v = row[k]; k += 1
                if c.endswith('position'): pos['XYZ'.index(c[0])] = v
                else: m = mm(m, rot(c[0], v))
            if parent < 0:
                R.append(m); P.append(pos)
            else:
                R.append(mm(R[parent], m)); P.append([a + b for a, b in zip(P[parent], mv(R[parent], pos))])
        out.append(P)
    return out

def find(joints, *cands):
    names = [j[0].lower() for j in joints]
    for c in cands:
        if c.lower() in names: return names.index(c.lower())
    raise SystemExit('no joint among %s' % (cands,))

def pct(v, p):
    s = sorted(v); return s[min(len(s) - 1, int(p * len(s)))]

def signals(path):
    joints, data, fps = parse_bvh(path)
    W = world(joints, data)
    J = dict(pelvis=find(joints, 'pelvis', 'hips'), head=find(joints, 'head'),
             lhand=find(joints, 'lhand', 'lefthand'), rhand=find(joints, 'rhand', 'righthand'),
             lank=find(joints, 'lfoot', 'leftfoot'), rank=find(joints, 'rfoot', 'rightfoot'),
             ltoe=find(joints, 'ltoes', 'lefttoe'), rtoe=find(joints, 'rtoes', 'righttoe'))
    n = len(W)
    y = lambda f, j: W[f][J[j]][1]
    floor = {j: pct([y(f, j) for f in range(n)], 0.02) for j in ('lank', 'rank', 'ltoe', 'rtoe')}
    ground = min(floor.values())
    H = pct([y(f, 'head') for f in range(n)], 0.9) - ground
    def rel_speed(f, j):
        a, b = max(0, f - 1), min(n - 1, f + 1)
        d = [(W[b][J[j]][k] - W[b][J['pelvis']][k]) - (W[a][J[j]][k] - W[a][J['pelvis']][k]) for k in range(3)]
        return math.sqrt(sum(x * x for x in d)) * fps / (b - a) / H
    def speed(f, j):
        a, b = max(0, f - 1), min(n - 1, f + 1)
        d = [W[b][J[j]][k] - W[a][J[j]][k] for k in range(3)]
        return math.sqrt(sum(x * x for x in d)) * fps / (b - a)
    rows = []
    for f in range(n):
        r = dict(frame=f, t=f / fps, pelvis_h=(y(f, 'pelvis') - ground) / H,
                 lhand=rel_speed(f, 'lhand'), rhand=rel_speed(f, 'rhand'),
                 lfoot=rel_speed(f, 'lank'), rfoot=rel_speed(f, 'rank'),
                 lfh=min(y(f, 'lank') - floor['lank'], y(f, 'ltoe') - floor['ltoe']),
                 rfh=min(y(f, 'rank') - floor['rank'], y(f, 'rtoe') - floor['rtoe']),
                 lfs=min(speed(f, 'lank'), speed(f, 'ltoe')), rfs=min(speed(f, 'rank'), speed(f, 'rtoe')))
        rows.append(r)
    return rows, fps, H

def png(path, w, h, pix):
    raw = b''.join(b'\x00' + bytes(pix[r * w * 3:(r + 1) * w * 3]) for r in range(h))
    def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0)) +
                           chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))

def plot(rows, fps, out, f0, f1, panels):
    w = 1600; ph = 90; h = ph * len(panels)
    pix = bytearray([255] * (w * h * 3))
    def put(x, y, c):
        if 0 <= x < w and 0 <= y < h: pix[(y * w + x) * 3:(y * w + x) * 3 + 3] = bytes(c)
    span = f1 - f0
    for p, (keys, top) in enumerate(panels):
        y0 = p * ph
        for x in range(w): put(x, y0, (0, 0, 0))
        # second ticks (every 1 s grey, 10 s dark)
        for s in range(int(f0 / fps), int(f1 / fps) + 1):
            x = int((s * fps - f0) / span * w)
            for yy in range(y0, y0 + ph): put(x, yy, (120, 120, 120) if s % 10 == 0 else (225, 225, 225))
        colours = [(200, 0, 0), (0, 0, 220), (0, 150, 0)]
        for ki, key in enumerate(keys):
            prev = None
            for f in range(f0, f1):
                x = int((f - f0) / span * w)
                v = min(top, max(0.0, rows[f][key]))
                yy = y0 + ph - 2 - int(v / top * (ph - 4))
                if prev is not None:
                    for t in range(min(prev, yy), max(prev, yy) + 1): put(x, t, colours[ki])
                prev = yy
    png(out, w, h, pix)

if __name__ == '__main__':
    ap = argparse.ArgumentParser()
    ap.add_argument('bvh'); ap.add_argument('--csv'); ap.add_argument('--png')
    ap.add_argument('--from', dest='t0', type=float, default=0.0); ap.add_argument('--to', dest='t1', type=float)
    a = ap.parse_args()
    rows, fps, H = signals(a.bvh)
    print('fps %.3f frames %d body height %.3f m' % (fps, len(rows), H))
    if a.csv:
        keys = list(rows[0].keys())
        with open(a.csv, 'w') as f:
            f.write(','.join(keys) + '\n')
            for r in rows: f.write(','.join('%.4g' % r[k] for k in keys) + '\n')
    if a.png:
        f0 = int(a.t0 * fps); f1 = min(len(rows), int((a.t1 if a.t1 else len(rows) / fps) * fps))
        plot(rows, fps, a.png, f0, f1, [(['pelvis_h'], 0.7), (['lhand', 'rhand'], 3.0), (['lfoot', 'rfoot'], 3.0),
                                        (['lfh', 'rfh'], 0.3), (['lfs', 'rfs'], 2.0)])
