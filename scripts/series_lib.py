"""Shared by the seeded series scripts (duel_series.py, chase_series.py):
plans one scene spec with fray-cli simulate and reads the scene back."""
import json
import os
import subprocess
import sys


def simulate(cli, project, spec, tmp):
    """Writes `spec` into the folder `tmp`, runs `fray-cli simulate` on it and
    returns (scene as a dict, the CLI's planning line). Exits with the CLI's
    message when it fails."""
    spec_file = os.path.join(tmp, "series.json")
    scene_file = os.path.join(tmp, "series.frayscene")
    with open(spec_file, "w") as f:
        json.dump(spec, f)
    run = subprocess.run([cli, "simulate", project, "--spec", spec_file, "--out", scene_file, "-q"],
                         capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(run.stderr.strip())
    with open(scene_file) as f:
        scene = json.load(f)
    lines = run.stdout.splitlines()
    return scene, lines[1] if len(lines) > 1 else ""
