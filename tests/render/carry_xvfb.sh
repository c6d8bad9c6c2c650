#!/usr/bin/env bash
# fray-play --carry under Xvfb with validation on: two carriers of one long
# box steered by a scripted --input (exits 0); the scripted turn changes the
# carriers' heading (the way the box travels, from the --log); a changed
# reward weight is recomputed in the background and comes into play; the
# carry graph built on the first run is kept and read on the next; a path
# (--path circle:3) is followed; bad input is one clear line before any window.
# Usage: carry_xvfb.sh FRAY_PLAY IMAGE_CHECK FRAY_CLI OUT_DIR
set -uo pipefail
play=$1 check=$2 cli=$3 out=$4
rm -rf "$out" && mkdir -p "$out"
source "$(dirname "$0")/xvfb_lib.sh"
start_xvfb 1024x768x24 || exit 1
"$cli" demo-library "$out/carry" --set carry --minutes 1 >"$out/lib.log" 2>&1 || { echo "FAIL: demo-library: $(cat "$out/lib.log")"; exit 1; }
p=$out/carry/demo.frayproj

cat >"$out/script.txt" <<'SCRIPT'
# Go the way carrier A faces (+Z) from 0.5 s, turn 90 degrees left at 4 s.
0.5 forward
4.0 turn-left
4.0 turn-left
# A reward weight changes: the eight policies are recomputed in the background.
5.0 set w_v=12
SCRIPT
# 100 frames of 0.1 s: 10 s. No graph yet: a small one is built before the window and kept.
run_window "fray-play --carry" "$out/carry.log" "$play" --carry "$p" --graph "$out/c.igraph" --graph-states 3000 --input "$out/script.txt" --log "$out/log.json" \
     --frames 100 --frame-time 0.1 --size 800x450 --validate --screenshot "$out/carry.png"
grep -q "c.igraph: no carry graph yet; building it (3000 states at most)" "$out/carry.log" || bad "no build message: $(cat "$out/carry.log")"
grep -q "drew 100 frames" "$out/carry.log" || bad "expected 100 frames: $(cat "$out/carry.log")"
grep -q "carrying at 10.000 s" "$out/carry.log" || bad "expected 10 s: $(cat "$out/carry.log")"
"$check" "$out/carry.png" 800 450 || bad "carry screenshot check"
"$cli" igraph stats "$out/c.igraph" >"$out/stats.log" 2>&1 || bad "the carry graph kept is not read: $(cat "$out/stats.log")"
python3 - "$out/log.json" <<'EOF2' || bad "the log: $(head -c 3000 "$out/log.json")"
import json, math, sys
log = json.load(open(sys.argv[1]))
assert log["format"] == "fray-play-log" and log["mode"] == "carry", "not a carry log"
ev = log["events"]
assert [e.get("command") for e in ev if "command" in e] == ["forward", "turn-left", "turn-left"], ev
assert all(e["source"] == "script" for e in ev), ev
box = log["box"]
def at(t):
    return min(box, key=lambda b: abs(b["time"] - t))
def way(t0, t1):
    a, b = at(t0), at(t1)
    return b["x"] - a["x"], b["z"] - a["z"]
# Before the command the pair holds; then it goes +Z; after the turn, +X (90 degrees left: sim::angleOf).
hx, hz = way(0.0, 0.5)
assert math.hypot(hx, hz) < 0.1, ("moved before the command", hx, hz)
fx, fz = way(1.5, 4.0)
sx, sz = way(6.0, 9.5)
assert math.hypot(fx, fz) > 0.4 and math.hypot(sx, sz) > 0.6, ("too little travel", fx, fz, sx, sz)
h1, h2 = math.atan2(fx, fz), math.atan2(sx, sz)
turned = (h2 - h1 + math.pi) % (2 * math.pi) - math.pi
assert abs(h1) < 0.5, ("first heading", h1)
assert 0.9 < turned < 2.2, ("the scripted turn did not turn the carriers' heading left", h1, h2)
dirs = [d["direction"] for d in log["decisions"] if d["time"] >= 6.0]
assert dirs and all(d >= 0 for d in dirs), ("holding after the turn", log["decisions"])
# The changed weight: recomputed in the background and in play after 5 s.
pol = log["policies"]
assert pol[0]["w_v"] == 8 and pol[0]["depth"] == 3, pol
assert any(p["w_v"] == 12 and p["time"] >= 5.0 and p["seconds"] > 0 for p in pol), pol
assert log["stats"]["grip_error_max"] < 0.05, log["stats"]
EOF2

# The graph kept is read on the next run; a path is followed.
run_window "fray-play --carry --path" "$out/path.log" "$play" --carry "$p" --graph "$out/c.igraph" --path circle:3 --log "$out/path.json" --frames 60 --frame-time 0.25 \
     --size 640x360 --validate --screenshot "$out/path.png"
grep -q "building" "$out/path.log" && bad "the kept graph was built again: $(cat "$out/path.log")"
python3 -c "
import json
log = json.load(open('$out/path.json'))
assert log['graph_read_seconds'] is not None and log['graph_read_seconds'] >= 0, log['graph_read_seconds']
assert log['stats']['path_error_mean'] < 0.5, log['stats']
assert log['stats']['grip_error_max'] < 0.05, log['stats']
" || bad "path log: $(head -c 2000 "$out/path.json")"

# Bad input: one line, exit code 1 (2: a usage error), before any window (no DISPLAY needed).
printf '1.0 forward\n2.0 jump\n' >"$out/bad.txt"
expect_play_error 1 "bad command" "bad.txt:2: 'jump' is not a carry command" --carry "$p" --graph "$out/c.igraph" --input "$out/bad.txt"
printf '1 set w_v=nan\n' >"$out/bad.txt"
expect_play_error 1 "bad weight" "bad.txt:1: reward weight w_v is not a finite number" --carry "$p" --graph "$out/c.igraph" --input "$out/bad.txt"
printf '1 heading north\n' >"$out/bad.txt"
expect_play_error 1 "bad heading" "bad.txt:1: heading 'north' is not a number of degrees" --carry "$p" --graph "$out/c.igraph" --input "$out/bad.txt"
printf '# a comment\n\ninf forward\n' >"$out/bad.txt"
expect_play_error 1 "infinite time" "bad.txt:3: 'inf' is not a time in seconds >= 0" --carry "$p" --graph "$out/c.igraph" --input "$out/bad.txt"
printf '2.5\n' >"$out/bad.txt"
expect_play_error 1 "no command" "bad.txt:1: a time without a command" --carry "$p" --graph "$out/c.igraph" --input "$out/bad.txt"
expect_play_error 1 "bad path" "--path: path 'circle:x'" --carry "$p" --graph "$out/c.igraph" --path circle:x
expect_play_error 1 "not a graph" "script.txt: exists and is not a carry graph file: not overwriting it" --carry "$p" --graph "$out/script.txt"
printf 'FRAYIGPH\x01\x00\x00\x00' >"$out/duel.igraph"
expect_play_error 1 "a duel's graph" "duel.igraph: a duel's interaction graph, not a carry graph: not overwriting it" --carry "$p" --graph "$out/duel.igraph"
grep -q "forward" "$out/script.txt" || bad "the file at the graph's place was changed"
expect_play_error 2 "path without carry" "--path is for --carry" --duel "$p" --path circle:3

finish_checks carry_xvfb
