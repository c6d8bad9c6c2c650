#!/usr/bin/env bash
# fray-play --duel / --teams under Xvfb with validation on: a scripted duel
# (--input) exits 0, the scripted punch launches a punch of the user's boxer
# (from its --log), the scripted style and depth change reaches the opponent
# as a recomputed policy, both boxers are drawn in the colours of their
# swatches; a team fight; a damaged graph is built again; bad input (a script
# line, a character that does not exist, a file at the graph's place that is
# not a graph, a project without attacks) is one clear line before any window.
# Usage: duel_xvfb.sh FRAY_PLAY IMAGE_CHECK DEMO_LIBRARY_DIR OUT_DIR FRAY_CLI
set -uo pipefail
play=$1 check=$2 lib=$3 out=$4 cli=$5
rm -rf "$out" && mkdir -p "$out"
source "$(dirname "$0")/xvfb_lib.sh"
start_xvfb 1024x768x24 || exit 1
p=$lib/demo.frayproj


cat >"$out/script.txt" <<'EOF'
# The user's boxer (character 0) only moves on command: it punches at 1 s.
1.0 punch
# The opponent turns outboxer at depth 2 (recomputed in the background).
1.5 style outboxer
1.5 depth 2
EOF
# 40 frames of 0.1 s: 4 s of the match. No graph yet: fray-play builds a
# small one of the demo project first (a counted run: before the window) and keeps it.
run_window "fray-play --duel" "$out/duel.log" "$play" --duel "$p" --graph "$out/g.igraph" --graph-states 3000 --input "$out/script.txt" --log "$out/log.json" \
     --frames 40 --frame-time 0.1 --size 800x450 --validate --screenshot "$out/duel.png"
grep -q "g.igraph: no graph yet; building it (3000 states at most)" "$out/duel.log" || bad "no build message: $(cat "$out/duel.log")"
"$cli" igraph stats "$out/g.igraph" >"$out/stats.log" 2>&1 || bad "the graph kept is not read: $(cat "$out/stats.log")"
grep -q "drew 40 frames" "$out/duel.log" || bad "expected 40 frames: $(cat "$out/duel.log")"
grep -q "match at 4.000 s" "$out/duel.log" || bad "expected the match at 4 s: $(cat "$out/duel.log")"
"$check" "$out/duel.png" 800 450 || bad "duel screenshot check"
# You (side 0) in red and the opponent (side 1) in blue, as their swatches
# (and the log's tints): the panel hidden, its widgets are blue too.
run_window "fray-play --duel --hide-panel" "$out/colours.log" "$play" --duel "$p" --graph "$out/g.igraph" --frames 3 --size 640x360 --hide-panel --validate \
     --screenshot "$out/colours.png"
"$check" "$out/colours.png" --tint $tint_red 300 || bad "the red boxer is not drawn"
"$check" "$out/colours.png" --tint $tint_blue 300 || bad "the blue boxer is not drawn"
python3 - "$out/log.json" <<'EOF' || bad "the log: $(head -c 3000 "$out/log.json")"
import json, sys
log = json.load(open(sys.argv[1]))
assert log["format"] == "fray-play-log" and log["mode"] == "duel", "not a duel log"
names = [c["name"] for c in log["characters"]]
assert names == ["you", "opponent"], names
# The tints drawn and swatched: render::sideColor (side 0 red, side 1 blue).
close = lambda a, b: all(abs(x - y) < 1e-6 for x, y in zip(a, b))
assert close(log["characters"][0]["tint"], [0.80, 0.30, 0.25]), log["characters"][0]
assert close(log["characters"][1]["tint"], [0.25, 0.45, 0.80]), log["characters"][1]
cmds = [e for e in log["events"] if e.get("command") == "punch"]
assert cmds and cmds[0]["source"] == "script" and abs(cmds[0]["time"] - 1.0) < 1e-6, log["events"]
mine = [a for a in log["actions"] if a["character"] == 0]
punches = [a for a in mine if "punch" in a["tags"]]
# The user's boxer never attacks unbidden: no punch before the command.
assert not [a for a in punches if a["start"] < 1.0], ("a punch before the command", punches)
# The punch starts at the next decision (the end of the action playing, or
# one step into a guard first): within 2.5 s of the command.
assert [a for a in punches if 1.0 <= a["start"] <= 3.5], ("no punch within 2.5 s of the command", mine)
# The opponent's recomputed policy is in play.
assert any(p["style"] == "outboxer" and p["depth"] == 2 and p["time"] >= 1.5 for p in log["policies"]), log["policies"]
assert log["policies"][0]["style"] == "general" and log["policies"][0]["depth"] == 3, log["policies"]
EOF

# A team fight of 8, the user steering red 1.
echo "0.5 forward" >"$out/teams.txt"
run_window "fray-play --teams" "$out/teams.log" "$play" --teams 8 "$p" --graph "$out/g.igraph" --input "$out/teams.txt" --log "$out/teams.json" \
     --frames 10 --frame-time 0.1 --size 640x360 --validate --screenshot "$out/teams.png"
"$check" "$out/teams.png" 640 360 || bad "teams screenshot check"
python3 -c "
import json, sys
log = json.load(open('$out/teams.json'))
assert log['mode'] == 'teams' and len(log['characters']) == 8, log['characters']
assert [c['side'] for c in log['characters']] == [0, 1] * 4
assert log['characters'][1]['name'] == 'blue 1'
" || bad "teams log: $(head -c 2000 "$out/teams.json")"

# A damaged graph is built again (with a message) and kept: the same bytes as before.
cp "$out/g.igraph" "$out/damaged.igraph"
printf '\x00\x00\x00\x00' | dd of="$out/damaged.igraph" bs=1 seek=4000 conv=notrunc 2>/dev/null
if ! timeout 120 "$play" --duel "$p" --graph "$out/damaged.igraph" --graph-states 3000 --frames 2 --size 320x200 \
     >"$out/damaged.log" 2>&1; then
  bad "fray-play on a damaged graph failed: $(cat "$out/damaged.log")"
fi
grep -q "damaged.igraph: the graph file is truncated or corrupt.*; building it again" "$out/damaged.log" ||
  bad "damaged graph message: $(cat "$out/damaged.log")"
cmp -s "$out/g.igraph" "$out/damaged.igraph" || bad "the graph built again differs from the first"

# Bad input: one line naming the file and line, exit code 1 (2: a usage error), before any window (no DISPLAY needed).
printf '1.0 punch\n\n2.0 jump\n' >"$out/bad.txt"
expect_play_error 1 "bad command" "bad.txt:3: 'jump' is not a command" --duel "$p" --graph "$out/g.igraph" --input "$out/bad.txt"
printf 'soon punch\n' >"$out/bad.txt"
expect_play_error 1 "bad time" "bad.txt:1: 'soon' is not a time" --duel "$p" --graph "$out/g.igraph" --input "$out/bad.txt"
printf '1 depth 0\n' >"$out/bad.txt"
expect_play_error 1 "bad depth" "bad.txt:1: depth '0' is not a whole number from 1 to 10" --duel "$p" --graph "$out/g.igraph" --input "$out/bad.txt"
printf '1 style brawler\n' >"$out/bad.txt"
expect_play_error 1 "bad style" "bad.txt:1: no boxing style named 'brawler'" --duel "$p" --graph "$out/g.igraph" --input "$out/bad.txt"
printf '# two characters\n1.0 kick 5\n' >"$out/bad.txt"
expect_play_error 1 "no such character" "bad.txt:2: character 5: the match has 2 characters" --duel "$p" --graph "$out/g.igraph" --input "$out/bad.txt"
echo '{"version": 1, "commands": [{"time": 1, "command": "punch"}, {"time": 2, "command": "jump"}]}' >"$out/bad.json"
expect_play_error 1 "bad JSON command" "bad.json: /commands/1/command: 'jump' is not a command" --duel "$p" --graph "$out/g.igraph" --input "$out/bad.json"
expect_play_error 1 "not a graph" "script.txt: exists and is not an interaction graph file: not overwriting it" --duel "$p" --graph "$out/script.txt"
grep -q "punch" "$out/script.txt" || bad "the file at the graph's place was changed"
# A project of walking alone: nothing to box with; no graph is written.
mkdir -p "$out/walk" && cp "$lib/walking.bvh" "$out/walk/"
"$cli" project new "$out/walk/w.frayproj" --import "$out/walk/walking.bvh" >"$out/walk.log" 2>&1 || bad "project new: $(cat "$out/walk.log")"
expect_play_error 1 "no attacks" "w.frayproj: Interaction Graph: the project has no" --duel "$out/walk/w.frayproj"
[[ -e "$out/walk/w.frayproj.igraph" ]] && bad "a graph was written for a project without attacks"
expect_play_error 2 "not a project" "--duel/--teams: give one project" --duel "$out/script.txt"

finish_checks duel_xvfb
