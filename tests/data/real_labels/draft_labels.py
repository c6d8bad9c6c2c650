#!/usr/bin/env python3
"""First draft of the action ranges of a take, to be checked and corrected by eye.

Marks the spans where the body moves: any hand or foot faster than 0.15 body
heights per second (H/s) relative to the pelvis; gaps under 0.2 s closed, spans
under 0.15 s dropped. Each span is then widened to where the movement is
visible: back while an effector is faster than 0.05 H/s (the onset), forward
while a hand (relative to the pelvis) or a foot (in the world) is (the end,
so the pelvis settling into a stance does not count). Where two widened spans
overlap, they meet at the quietest frame between the narrow spans. For each
span the effector with the highest peak is printed. Prints the spans. The labels committed here were edited from this draft
after looking at the plots (see README.md); the draft is not the truth.

  python3 draft_labels.py take.bvh    # take.bvh: `fray-cli convert CAPTURE take.bvh`
"""
import argparse, sys, os
sys.path.insert(0, os.path.dirname(__file__))
import inspect_take as it

def spans(rows, fps, H, level=0.15, gap=0.2, shortest=0.15):
    moving = [max(r['lhand'], r['rhand'], r['lfoot'], r['rfoot']) > level for r in rows]
    out = []; f = 0; n = len(rows)
    while f < n:
        if not moving[f]: f += 1; continue
        a = f
        while f < n and moving[f]: f += 1
        if out and a - out[-1][1] <= gap * fps: out[-1][1] = f - 1
        else: out.append([a, f - 1])
    out = [s for s in out if s[1] - s[0] + 1 >= shortest * fps]
    act = lambda r: max(r['lhand'], r['rhand'], r['lfoot'], r['rfoot'])
    still = lambda r: max(r['lhand'], r['rhand'], r['lfs'] / H, r['rfs'] / H)
    wide = []
    for a, b in out:
        while a > 0 and act(rows[a - 1]) > 0.05: a -= 1
        while b < n - 1 and still(rows[b + 1]) > 0.05: b += 1
        wide.append([a, b])
    for i in range(len(wide) - 1):
        if wide[i][1] >= wide[i + 1][0]:
            q = min(range(out[i][1], out[i + 1][0] + 1), key=lambda f: act(rows[f]))
            wide[i][1] = q - 1; wide[i + 1][0] = q
    return wide

if __name__ == '__main__':
    ap = argparse.ArgumentParser()
    ap.add_argument('bvh')
    a = ap.parse_args()
    rows, fps, H = it.signals(a.bvh)
    for s in spans(rows, fps, H):
        peak = {k: max(r[k] for r in rows[s[0]:s[1] + 1]) for k in ('lhand', 'rhand', 'lfoot', 'rfoot')}
        best = max(peak, key=peak.get)
        print('%5d %5d  %.2f-%.2f s  %s %.2f H/s  (%s)' % (s[0], s[1], s[0] / fps, s[1] / fps, best, peak[best],
              ' '.join('%s=%.1f' % kv for kv in peak.items())))
