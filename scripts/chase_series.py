#!/usr/bin/env python3
"""Seeded chase series through fray-cli simulate (thesis 4.5.2 experiments).

Runs N chases on the running take: one or more chasers (preset chaser, depth
DC) against one runaway (preset runaway, depth DR), starting 2 m apart with a
small seeded offset, each ending at the first catch or after S seconds. Prints
per seed the catch time and at the end the share caught and the mean time to
catch, counting a chase without a catch as S (a lower bound on the mean).

  python3 scripts/chase_series.py PROJECT --depth-chaser 4 --depth-runaway 2 --chasers 1 --matches 8
"""
import argparse
import tempfile

from series_lib import simulate


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("project")
    ap.add_argument("--cli", default="build/bin/fray-cli")
    ap.add_argument("--depth-chaser", type=int, default=4)
    ap.add_argument("--depth-runaway", type=int, default=2)
    ap.add_argument("--chasers", type=int, default=1, choices=[1, 2, 3])
    ap.add_argument("--motion", default="running_around")
    ap.add_argument("--matches", type=int, default=8)
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--arena", type=float, default=0.0, help="radius (m) of a disc stage centred between them; 0: none")
    args = ap.parse_args()
    caught = 0
    total = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, args.matches + 1):
            chars = [{"name": "runaway", "side": 1, "preset": "runaway", "depth": args.depth_runaway,
                      "motions": [args.motion], "start": {"x": 2, "z": 0, "heading_deg": 90}}]
            # Chasers side by side behind the runaway's start.
            for k in range(args.chasers):
                chars.append({"name": f"chaser{k + 1}", "side": 0, "preset": "chaser", "depth": args.depth_chaser,
                              "motions": [args.motion],
                              "start": {"x": 0, "z": 1.2 * k - 0.6 * (args.chasers - 1), "heading_deg": 90}})
            spec = {"version": 1, "duration": args.seconds, "seed": seed, "stop_on_catch": True,
                    "start_jitter": {"distance": 0.3, "angle_deg": 20}, "characters": chars}
            if args.arena > 0:
                spec["arena"] = {"x": 1, "z": 0, "radius": args.arena}
            scene, planning = simulate(args.cli, args.project, spec, tmp)
            times = [c["time"] for c in scene["catches"]]
            t = min(times) if times else None
            caught += t is not None
            total += t if t is not None else args.seconds
            print(f"seed {seed}: " + (f"caught at {t:.2f} s" if t is not None else "not caught"), flush=True)
    print(f"{args.chasers} chaser(s) at depth {args.depth_chaser} vs runaway at depth {args.depth_runaway}: "
          f"caught {caught} of {args.matches}, mean time to catch {total / args.matches:.2f} s "
          f"(no catch counted as {args.seconds:g} s)")


if __name__ == "__main__":
    main()
