#!/usr/bin/env bash
# The Interaction Graph's carrying from the command line on the demo actor's
# carry set: two carriers follow a circle (an ordinary scene that metrics
# reads), a path file, and bad input: the duel's graph of a project with no
# attack actions, a non-finite carry weight, a broken path. Each is a
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
expect_fail "carry with a graph file" "the carry graph is built in memory" "$cli" igraph play "$p" --kind carry --graph "$tmp/g.igraph" -o "$tmp/x.frayscene" -q
check "no scene or graph from bad input" "[ ! -e '$tmp/x.frayscene' ] && [ ! -e '$tmp/g.igraph' ]"
echo "cli_igraph_carry: ok"
