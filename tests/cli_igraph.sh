#!/usr/bin/env bash
# The Interaction Graph from the command line on a small demo project: build
# (same seed, same bytes), stats, policy, a duel with a scripted punch that
# metrics and export read like any scene; and bad input: a damaged graph, a
# file that is not a graph, a non-finite reward weight, an unknown command.
# Each is a one-line error that leaves the files untouched.
set -eu
cli=$1
. "$(dirname "$0")/cli_lib.sh"

"$cli" demo-library "$tmp/lib" --minutes 3 > /dev/null 2>&1
p=$tmp/lib/demo.frayproj
"$cli" igraph build "$p" --max-states 3000 -o "$tmp/g.igraph" 2> "$tmp/progress.txt" > "$tmp/build.txt"
check "build summary" "grep -q 'states' '$tmp/build.txt' && grep -q 'coverage' '$tmp/build.txt'"
check "build report" "grep -q 'build_seconds' '$tmp/g.igraph.build.json'"
"$cli" igraph build "$p" --max-states 3000 -o "$tmp/again.igraph" -q > /dev/null
check "same seed, same bytes" "cmp -s '$tmp/g.igraph' '$tmp/again.igraph'"
"$cli" igraph stats "$tmp/g.igraph" --json > "$tmp/stats.json"
check "stats json" "grep -q '\"edges\"' '$tmp/stats.json' && grep -q '\"coverage\"' '$tmp/stats.json' && grep -q '\"build_seconds\": [0-9]' '$tmp/stats.json'"
"$cli" igraph policy "$tmp/g.igraph" --preset outboxer --depth 5 > "$tmp/policy.txt"
check "policy" "grep -q 'policy outboxer depth 5' '$tmp/policy.txt'"

# A duel where character 0 only moves on command: the scripted punch is a punch.
echo '{"version": 1, "commands": [{"time": 2.0, "command": "punch"}]}' > "$tmp/cmd.json"
"$cli" igraph play "$p" --graph "$tmp/g.igraph" --kind duel --seconds 5 --you static --opponent static \
  --input "$tmp/cmd.json" -o "$tmp/duel.frayscene" -q > "$tmp/play.txt"
check "command carried out" "grep -q '1 of 1 commands carried out' '$tmp/play.txt'"
check "scene written" "grep -q '\"format\": \"fray-scene\"' '$tmp/duel.frayscene'"
"$cli" metrics "$tmp/duel.frayscene" -q > "$tmp/metrics.txt"
check "metrics read the scene" "grep -q '^you' '$tmp/metrics.txt'"
"$cli" igraph play "$p" --graph "$tmp/g.igraph" --kind teams --characters 8 --seconds 4 -o "$tmp/teams.frayscene" -q > /dev/null
"$cli" metrics "$tmp/teams.frayscene" --json -q > /dev/null
check "team scene" "grep -q 'blue 4' '$tmp/teams.frayscene'"

# Table 5.1, tiny: the static target and a tree-expansion boxer at depth 2.
"$cli" igraph table "$p" --graph "$tmp/g.igraph" --matches 2 --seconds 4 --depths 1 --tree-depths 2 -q > "$tmp/table.txt"
check "table columns" "grep -q 'vs tree expansion depth 2' '$tmp/table.txt' && grep -q '^| 1 | ' '$tmp/table.txt'"
check "tree expansion decided" "grep -Eq 'tree expansion depth 2: [1-9][0-9]* decisions' '$tmp/table.txt'"
# The same with refined look-ups, two depths and the prediction measurement.
"$cli" igraph table "$p" --graph "$tmp/g.igraph" --matches 2 --seconds 4 --depths 1 3 --tree-depths 2 --refine --set gamma=0.5 --measure -q > "$tmp/table2.txt"
check "table: paired differences" "grep -q '^| 3 - 1 | ' '$tmp/table2.txt'"
check "table: measured look-ups" "grep -Eq '^\\| 3 \\| tree expansion depth 2 \\| [1-9][0-9]* \\| ' '$tmp/table2.txt'"
expect_fail "table: bad opponent model" "is not own or mine" "$cli" igraph table "$p" --graph "$tmp/g.igraph" --set opponent=both -q
check "table: refined, gamma 0.5 by default" "grep -q 'refined look-ups, gamma 0.5;' '$tmp/table.txt' && grep -q '(seeds 1-2)' '$tmp/table.txt'"
"$cli" igraph table "$p" --graph "$tmp/g.igraph" --matches 1 --first-seed 5 --seconds 2 --depths 1 --tree-depths 2 --plain -q > "$tmp/table3.txt"
check "table: --plain keeps the style's gamma, --first-seed" "grep -q 'plain look-ups, gamma 1;' '$tmp/table3.txt' && grep -q '(seeds 5-5)' '$tmp/table3.txt'"
expect_fail "table: --plain with --refine" "exclude each other" "$cli" igraph table "$p" --graph "$tmp/g.igraph" --plain --refine -q
expect_fail "table: unknown tree preset" "no planner preset named 'nobody'" "$cli" igraph table "$p" --graph "$tmp/g.igraph" --tree-preset nobody -q

# Bad input.
cp "$tmp/g.igraph" "$tmp/bad.igraph"
printf '\x00\x00\x00\x00' | dd of="$tmp/bad.igraph" bs=1 seek=4000 conv=notrunc 2> /dev/null
expect_fail "damaged graph" "bad.igraph: the graph file is truncated or corrupt" "$cli" igraph stats "$tmp/bad.igraph"
expect_fail "damaged graph in play" "bad.igraph: the graph file is truncated or corrupt" \
  "$cli" igraph play "$p" --graph "$tmp/bad.igraph" -o "$tmp/x.frayscene" -q
expect_fail "not a graph" "not a Fray interaction graph file" "$cli" igraph stats "$tmp/cmd.json"
expect_fail "non-finite weight" "reward weight w_a is not a finite number" "$cli" igraph policy "$tmp/g.igraph" --set w_a=nan
expect_fail "infinite weight" "reward weight w_theta is not a finite number" "$cli" igraph policy "$tmp/g.igraph" --set w_theta=inf
expect_fail "negative weight" "reward weight w_d is negative" "$cli" igraph policy "$tmp/g.igraph" --set w_d=-1
expect_fail "gamma above 1" "reward weight gamma must be in" "$cli" igraph policy "$tmp/g.igraph" --set gamma=2
head -c 100 "$tmp/g.igraph" > "$tmp/short.igraph"
expect_fail "truncated graph" "short.igraph: the graph file is truncated or corrupt" "$cli" igraph stats "$tmp/short.igraph"
: > "$tmp/empty.igraph"
expect_fail "empty graph file" "empty.igraph: not a Fray interaction graph file" "$cli" igraph stats "$tmp/empty.igraph"
expect_fail "unknown style" "no boxing style named 'brawler'" "$cli" igraph policy "$tmp/g.igraph" --preset brawler
echo '{"version": 1, "commands": [{"time": 1, "command": "jump"}]}' > "$tmp/bad.json"
expect_fail "bad command" "bad.json: /commands/0/command" \
  "$cli" igraph play "$p" --graph "$tmp/g.igraph" --input "$tmp/bad.json" -o "$tmp/y.frayscene" -q
check "no scene from bad input" "[ ! -e '$tmp/x.frayscene' ] && [ ! -e '$tmp/y.frayscene' ]"
expect_fail "graph over a non-graph" "not overwriting" "$cli" igraph build "$p" -o "$tmp/cmd.json" -q
check "the other file kept" "grep -q punch '$tmp/cmd.json'"
echo "cli_igraph: ok"
