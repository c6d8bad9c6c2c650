#!/usr/bin/env python3
"""Puts the hand labels of this folder on a Fray project's takes (tests/cli_mixed_duel.sh).

Usage: label_project.py PROJECT.frayproj

For every project motion whose capture is labelled here (actions.csv,
falls.csv; matched by file name), the cuts and annotations are replaced by
the labels: each labelled span starts an action (punch, kick, block, step,
transition, falling; a get-up is a transition), a rest of 0.75 s or more
after it is an idle action of its own (the rule of realcap_fixture.h's
trueCuts), a shorter rest stays with the action before it, and the frames
before the first label are an idle action. Every other motion keeps its
segmentation and has its automatic proposals confirmed (what a user who
accepts them all gets). The project is rewritten in place.
"""
import csv
import json
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
# Capture rates of the labelled takes (README.md): CMU 135 at 120 fps, LAFAN1 at 30.
FPS = {'oiduki001.bvh': 120.0, 'frontkick001.bvh': 120.0, 'gedanbarai.bvh': 120.0, 'fallAndGetUp3_subject1.bvh': 30.0}
WORDS = {'punch': ['punch'], 'kick': ['kick'], 'block': ['block'], 'step': ['step'],
         'transition': ['transition'], 'falling': ['falling'], 'getup': ['transition']}


def labels():
    out = {}
    for name in ('actions.csv', 'falls.csv'):
        with open(HERE / name) as f:
            for row in csv.reader(line for line in f if not line.startswith('#')):
                take = pathlib.Path(row[0]).name
                out.setdefault(take, []).append((int(row[1]), int(row[2]), row[3]))
    return out


def action(annotations):
    return {'name': '', 'annotations': annotations, 'proposed': [], 'joints': [], 'attack_direction': None,
            'defended_part': None, 'initial_conditions': None}


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    path = pathlib.Path(sys.argv[1])
    project = json.loads(path.read_text())
    rows = labels()
    for m in project['motions']:
        mine = sorted(rows.get(pathlib.Path(m['path']).name, []))
        if not mine:
            for a in m['actions']:
                a['annotations'] = sorted(set(a['annotations']) | set(a['proposed']))
                a['proposed'] = []
            continue
        frames = m['frame_count']
        fps = FPS[pathlib.Path(m['path']).name]
        starts = [] if mine[0][0] == 0 else [(0, ['idle'])]
        for i, (first, last, label) in enumerate(mine):
            if label not in WORDS:
                sys.exit(f'{m["path"]}: unknown label {label!r}')
            starts.append((first, WORDS[label]))
            following = mine[i + 1][0] if i + 1 < len(mine) else frames
            if last + 1 < frames and following - last - 1 >= 0.75 * fps:
                starts.append((last + 1, ['idle']))
        starts = [s for s in starts if s[0] < frames]
        m['cuts'] = [s[0] for s in starts[1:]]
        m['actions'] = [action(s[1]) for s in starts]
    path.write_text(json.dumps(project, indent=1) + '\n')


if __name__ == '__main__':
    main()
