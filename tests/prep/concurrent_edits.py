#!/usr/bin/env python3
"""Concurrent edits of one project: ROUNDS rounds of two, then of four
fray-cli writers (`combos set` and `presets set`) started together on the
same project file. After every round the file must parse, and every edit must
either be in it (the writer exited 0) or have been refused with a message on
stderr (non-zero exit). An edit that exited 0 but is missing was lost.

usage: concurrent_edits.py FRAY_CLI [ROUNDS]
"""
import json
import os
import subprocess
import sys
import tempfile


def main():
    cli = sys.argv[1]
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    failures = []
    with tempfile.TemporaryDirectory(prefix="fray_concurrent_") as tmp:
        project = os.path.join(tmp, "p.frayproj")
        with open(project, "w") as f:
            f.write('{"format": "fray-project", "version": 1, "name": "p", "motions": []}\n')
        applied = refused = 0
        for writers in (2, 4):
            for r in range(rounds):
                value = writers * 1000 + r
                edits = []
                for w in range(writers):
                    if w % 2 == 0:
                        args = ["combos", project, "set", "jab%d" % w, "@block", str(value)]
                        check = ("combo", "jab%d" % w, value)
                    else:
                        args = ["presets", project, "set", "style%d" % w, "w_r=%d" % value]
                        check = ("preset", "style%d" % w, value)
                    edits.append((args, check))
                procs = [subprocess.Popen([cli] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
                         for args, _ in edits]
                results = [(p.wait(timeout=120), p.stderr.read().decode(errors="replace")) for p in procs]
                for p in procs:
                    p.stderr.close()
                try:
                    with open(project) as f:
                        doc = json.load(f)
                except ValueError as e:
                    failures.append("%d writers, round %d: unparseable project (%s)" % (writers, r, e))
                    # Start again from a good file so later rounds still test something.
                    with open(project, "w") as f:
                        f.write('{"format": "fray-project", "version": 1, "name": "p", "motions": []}\n')
                    continue
                for (args, (kind, name, v)), (rc, err) in zip(edits, results):
                    if kind == "combo":
                        present = any(c.get("mine") == name and c.get("suitability") == v
                                      for c in doc.get("combos", []))
                    else:
                        present = doc.get("planner_presets", {}).get(name, {}).get("w_r") == v
                    if rc == 0 and present:
                        applied += 1
                    elif rc != 0 and err.strip():
                        refused += 1
                    else:
                        failures.append("%d writers, round %d: %s exited %d, edit %s, stderr %r" %
                                        (writers, r, " ".join(args[:1] + args[2:]), rc,
                                         "present" if present else "LOST", err.strip()[:200]))
        leftovers = [n for n in os.listdir(tmp) if n.endswith(".tmp")]
        if leftovers:
            failures.append("temporary files left behind: %s" % leftovers)
    for f in failures[:20]:
        print("FAIL:", f)
    print("concurrent_edits: %d edits applied, %d refused with a message, %d failures" %
          (applied, refused, len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
