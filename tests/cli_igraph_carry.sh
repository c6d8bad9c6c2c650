#!/usr/bin/env bash
# The Interaction Graph's carrying from the command line on the demo actor's
# carry set: two carriers follow a circle (an ordinary scene that metrics
# reads), a path file, and bad input: the duel's graph of a project with no
# attack actions, a non-finite carry weight, a broken path, damaged or
# foreign carry graph files. Each is a
# one-line error that writes nothing.
set -eu
cli=$1
. "$(dirname "$0")/cli_lib.sh"

"$cli" demo-library "$tmp/carry" --set carry --minutes 1 > /dev/null 2>&1
p=$tmp/carry/demo.frayproj
"$cli" igraph play "$p" --kind carry --path circle:3 --seconds 30 --carry-states 6000 -o "$tmp/carry.frayscene" -q > "$tmp/play.txt"
check "carry summary" "grep -q 'carry graph: [0-9]* states' '$tmp/play.txt' && grep -q 'path error mean' '$tmp/play.txt'"
check "box in the scene" "grep -q '\"body\": \"box\"' '$tmp/carry.frayscene'"
"$cli" metrics "$tmp/carry.frayscene" -q > "$tmp/metrics.txt"
check "metrics read the scene" "grep -q '^carrier A' '$tmp/metrics.txt'"
echo '{"version": 1, "points": [[0, 0], [2, 0], [2, 2]]}' > "$tmp/path.json"
"$cli" igraph play "$p" --kind carry --path "$tmp/path.json" --seconds 10 --carry-states 3000 -o "$tmp/line.frayscene" -q > /dev/null
check "path file" "grep -q '\"kind\": \"path\"' '$tmp/line.frayscene'"

# Bad input.
expect_fail "no attacks: build" "the project has no attack actions" "$cli" igraph build "$p" -o "$tmp/g.igraph" -q
expect_fail "no attacks: duel" "the project has no attack actions" "$cli" igraph play "$p" --kind duel -o "$tmp/x.frayscene" -q
expect_fail "non-finite carry weight" "reward weight w_d is not a finite number" \
  "$cli" igraph play "$p" --kind carry --carry-set w_d=nan -o "$tmp/x.frayscene" -q
echo '{"version": 1, "points": [[0, 0], [1, "a"]]}' > "$tmp/bad.json"
expect_fail "bad path" "bad.json: /points/1" "$cli" igraph play "$p" --kind carry --path "$tmp/bad.json" -o "$tmp/x.frayscene" -q
expect_fail "bad circle" "the radius must be a number" "$cli" igraph play "$p" --kind carry --path circle:x -o "$tmp/x.frayscene" -q
check "no scene or graph from bad input" "[ ! -e '$tmp/x.frayscene' ] && [ ! -e '$tmp/g.igraph' ]"

# The carry graph file: igraph build --kind carry writes it (the same bytes
# every time), stats reads it, play loads it and plays as a graph built in memory.
"$cli" igraph build "$p" --kind carry --max-states 1500 -o "$tmp/c.igraph" -q > "$tmp/build.txt"
check "carry build summary" "grep -q 'c.igraph: carry graph, [0-9]* states, [0-9]* edges' '$tmp/build.txt'"
check "carry build report" "grep -q build_seconds '$tmp/c.igraph.build.json'"
"$cli" igraph build "$p" --kind carry --max-states 1500 -o "$tmp/c2.igraph" -q > /dev/null
check "same bytes every build" "cmp -s '$tmp/c.igraph' '$tmp/c2.igraph'"
"$cli" igraph stats "$tmp/c.igraph" > "$tmp/stats.txt"
check "stats: a carry graph" "grep -q 'carry graph (two carriers of a 1.60 m box' '$tmp/stats.txt' && grep -q '  build: [0-9.]* s, peak' '$tmp/stats.txt'"
"$cli" igraph stats "$tmp/c.igraph" --json > "$tmp/stats.json"
python3 - "$tmp/stats.json" <<'PY' || { echo "FAIL: stats --json: $(cat "$tmp/stats.json")"; exit 1; }
import json, sys
j = json.load(open(sys.argv[1]))
assert j["kind"] == "carry" and j["states"] > 1000 and j["edges"] > 10 * j["states"], j
assert j["memory_bytes"] > 0 and j["build_seconds"] > 0 and j["file_bytes"] > j["edges"] * 24, j
PY
"$cli" igraph policy "$tmp/c.igraph" --depth 3 --set w_v=12 > "$tmp/policy.txt"
check "carry policies from the file" "grep -q '8 carry policies depth 3 over [0-9]* states in' '$tmp/policy.txt'"
"$cli" igraph play "$p" --kind carry --graph "$tmp/c.igraph" --seconds 10 -o "$tmp/loaded.frayscene" -q > "$tmp/loaded.txt"
check "play reads the file" "grep -q 'read from .*c.igraph in' '$tmp/loaded.txt'"
"$cli" igraph play "$p" --kind carry --carry-states 1500 --seconds 10 -o "$tmp/built.frayscene" -q > "$tmp/built.txt"
check "built in memory without a file" "grep -q 'built in' '$tmp/built.txt'"
check "loaded and built graphs play alike" \
  "[ \"\$(grep -o 'decisions.*' '$tmp/loaded.txt')\" = \"\$(grep -o 'decisions.*' '$tmp/built.txt')\" ]"
# PROJECT.carry.igraph is read when present; a damaged one is not trusted: built in memory, with a message.
cp "$tmp/c.igraph" "$p.carry.igraph"
"$cli" igraph play "$p" --kind carry --seconds 5 -o "$tmp/default.frayscene" -q > "$tmp/default.txt"
check "play reads the default file" "grep -q 'read from .*demo.frayproj.carry.igraph' '$tmp/default.txt'"
printf '\x00\x00\x00\x00' | dd of="$p.carry.igraph" bs=1 seek=3000 conv=notrunc 2>/dev/null
"$cli" igraph play "$p" --kind carry --seconds 5 --carry-states 1500 -o "$tmp/rebuilt.frayscene" -q > "$tmp/rebuilt.txt" 2> "$tmp/rebuilt.err"
check "damaged default: message" "grep -q 'carry.igraph: the carry graph file is truncated or corrupt.*building the carry graph in memory' '$tmp/rebuilt.err'"
check "damaged default: built" "grep -q 'built in' '$tmp/rebuilt.txt'"
# Bad graph files given with --graph: refused, nothing written.
cp "$tmp/c.igraph" "$tmp/damaged.igraph"
printf '\x00\x00\x00\x00' | dd of="$tmp/damaged.igraph" bs=1 seek=3000 conv=notrunc 2>/dev/null
expect_fail "damaged carry graph" "damaged.igraph: the carry graph file is truncated or corrupt" \
  "$cli" igraph play "$p" --kind carry --graph "$tmp/damaged.igraph" -o "$tmp/x.frayscene" -q
expect_fail "damaged carry graph: stats" "damaged.igraph: the carry graph file is truncated or corrupt" "$cli" igraph stats "$tmp/damaged.igraph"
printf 'FRAYIGPH\x01\x00\x00\x00not really' > "$tmp/duel.igraph"
expect_fail "a duel's graph" "duel.igraph: an interaction graph for a duel or team fight" \
  "$cli" igraph play "$p" --kind carry --graph "$tmp/duel.igraph" -o "$tmp/x.frayscene" -q
expect_fail "not a graph" "path.json: not a Fray carry graph file" "$cli" igraph play "$p" --kind carry --graph "$tmp/path.json" -o "$tmp/x.frayscene" -q
expect_fail "other --carry-states" "was built with 1500" \
  "$cli" igraph play "$p" --kind carry --graph "$tmp/c.igraph" --carry-states 5000 -o "$tmp/x.frayscene" -q
expect_fail "not overwriting" "path.json: exists and is not a carry graph file: not overwriting it" \
  "$cli" igraph build "$p" --kind carry -o "$tmp/path.json" -q
expect_fail "a preset for a carry graph" "boxing styles are for a duel" "$cli" igraph policy "$tmp/c.igraph" --preset outboxer
check "bad input wrote nothing" "[ ! -e '$tmp/x.frayscene' ] && grep -q points '$tmp/path.json'"
echo "cli_igraph_carry: ok"
