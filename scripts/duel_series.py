#!/usr/bin/env python3
"""Seeded duel series through fray-cli simulate (thesis 4.5.1 experiments).

Runs N matches of two general boxers, A at depth DA from motion MA against B at
depth DB from motion MB, each seed with a small random start offset, and counts
the matches A wins (more successful hits than B), those B wins and the draws,
with standard errors: the wins' binomial one and the per-match hits' sample one.

  python3 scripts/duel_series.py PROJECT --depth-a 4 --depth-b 2 --matches 20 --seconds 20
"""
import argparse
import math
import tempfile

from series_lib import simulate

ACTIONS = ["@punch", "@kick", "@block", "@avoid", "@step", "@idle", "@transition", "@turn"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("project")
    ap.add_argument("--cli", default="build/bin/fray-cli")
    ap.add_argument("--depth-a", type=int, default=4)
    ap.add_argument("--depth-b", type=int, default=2)
    ap.add_argument("--motion-a", default="shadowbox_energetic")
    ap.add_argument("--motion-b", default="shadowbox_energetic")
    ap.add_argument("--matches", type=int, default=20)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--leaf-budget", type=int, default=None, help="leaves one decision may visit (the spec's leaf_budget)")
    ap.add_argument("--root-beam", type=int, default=None,
                    help="root children the deepest search pass keeps (the spec's root_beam; 0: the exact search)")
    args = ap.parse_args()
    wins = 0
    losses = 0
    total = [0, 0]
    per_match = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.matches + 1):
            spec = {"version": 1, "duration": args.seconds, "seed": seed,
                    "start_jitter": {"distance": 0.3, "angle_deg": 20},
                    "characters": [
                        {"name": "a", "side": 0, "depth": args.depth_a, "motions": [args.motion_a], "actions": ACTIONS,
                         "start": {"x": 0, "z": 0, "heading_deg": 90}},
                        {"name": "b", "side": 1, "depth": args.depth_b, "motions": [args.motion_b], "actions": ACTIONS,
                         "start": {"x": 1.1, "z": 0, "heading_deg": -90}}]}
            if args.leaf_budget:
                spec["leaf_budget"] = args.leaf_budget
            if args.root_beam is not None:
                spec["root_beam"] = args.root_beam
            scene, planning = simulate(args.cli, args.project, spec, tmp)
            hits = [0, 0]
            for h in scene["hits"]:
                if not h["blocked"]:
                    hits[h["attacker"]] += 1
            total[0] += hits[0]
            total[1] += hits[1]
            wins += hits[0] > hits[1]
            losses += hits[1] > hits[0]
            per_match.append(hits)
            print(f"seed {seed}: hits A {hits[0]} B {hits[1]}  ({planning.split(',')[0]})", flush=True)
    print(f"A (depth {args.depth_a}, {args.motion_a}) won {wins} of {args.matches} matches; "
          f"hits {total[0]} vs {total[1]}")
    n = len(per_match)
    if n > 1:
        def se(xs):
            m = sum(xs) / n
            return math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n)
        p = wins / n
        print(f"A won {wins}, B won {losses}, draws {n - wins - losses}; A's wins {wins} +- {n * math.sqrt(p * (1 - p) / n):.1f} "
              f"(binomial standard error); hits per match A {total[0] / n:.2f} +- {se([h[0] for h in per_match]):.2f}, "
              f"B {total[1] / n:.2f} +- {se([h[1] for h in per_match]):.2f}, A - B {(total[0] - total[1]) / n:.2f} +- "
              f"{se([h[0] - h[1] for h in per_match]):.2f} (standard errors)")


if __name__ == "__main__":
    main()
