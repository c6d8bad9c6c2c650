#!/usr/bin/env bash
# Interaction Graph setups (graph-duel, graph-teams, graph-carry) stored in
# the project and run by `simulate --setup`: the scene is byte-identical to
# the one `igraph play` writes for the same parameters, whether the graph is
# built in memory (no graph file) or read from the file beside the project;
# bad parameters are one-line errors naming the field; compose refuses them.
set -eu
cli=$1
. "$(dirname "$0")/cli_lib.sh"

"$cli" demo-library "$tmp/lib" --minutes 3 > /dev/null 2>&1
p=$tmp/lib/demo.frayproj
cd "$tmp"

# graph-duel against a static target, no graph file yet: built in memory.
echo '{"kind": "graph-duel", "duration": 5, "seed": 2, "opponent": "static", "depth": 2, "graph_states": 3000}' > duel.json
"$cli" setup "$p" import gduel --spec duel.json -q > /dev/null
check "section version 2" "grep -q '\"graph-duel\"' '$p'"
"$cli" simulate "$p" --setup gduel -o setup-duel.frayscene -q > sim.txt
check "built in memory" "grep -q 'graph: built in memory' sim.txt"
"$cli" igraph build "$p" --max-states 3000 -o g.igraph -q > /dev/null
"$cli" igraph play "$p" --graph g.igraph --kind duel --seconds 5 --seed 2 --opponent static --depth 2 -o play-duel.frayscene -q > /dev/null
check "graph-duel = igraph play (graph built in memory)" "cmp -s setup-duel.frayscene play-duel.frayscene"
# The graph file beside the project is read when it is valid.
cp g.igraph "$p.igraph"
"$cli" simulate "$p" --setup gduel -o setup-duel2.frayscene -q > sim2.txt
check "graph file read" "grep -q 'graph: demo.frayproj.igraph' sim2.txt"
check "graph-duel = igraph play (graph file)" "cmp -s setup-duel2.frayscene play-duel.frayscene"

# graph-teams: 3 against 3, and 3 against 2 (igraph play --characters 5).
echo '{"kind": "graph-teams", "duration": 4, "seed": 3, "red": 3, "blue": 3, "opponent_style": "outboxer"}' > teams.json
"$cli" setup "$p" import gteams --spec teams.json -q > /dev/null
"$cli" simulate "$p" --setup gteams -o setup-teams.frayscene -q > /dev/null
"$cli" igraph play "$p" --kind teams --characters 6 --seconds 4 --seed 3 --opponent-preset outboxer -o play-teams.frayscene -q > /dev/null
check "graph-teams = igraph play" "cmp -s setup-teams.frayscene play-teams.frayscene"
echo '{"kind": "graph-teams", "duration": 4, "seed": 3, "red": 3, "blue": 2}' > teams5.json
"$cli" setup "$p" import gteams5 --spec teams5.json -q > /dev/null
"$cli" simulate "$p" --setup gteams5 -o setup-teams5.frayscene -q > /dev/null
"$cli" igraph play "$p" --kind teams --characters 5 --seconds 4 --seed 3 -o play-teams5.frayscene -q > /dev/null
check "graph-teams 3 vs 2 = igraph play --characters 5" "cmp -s setup-teams5.frayscene play-teams5.frayscene"
echo '{"kind": "graph-teams", "duration": 4, "seed": 3, "red": 1, "blue": 4}' > teams14.json
"$cli" setup "$p" import gteams14 --spec teams14.json -q > /dev/null
"$cli" simulate "$p" --setup gteams14 -o setup-teams14.frayscene -q > /dev/null
check "1 vs 4" "grep -q '\"blue 4\"' setup-teams14.frayscene && ! grep -q '\"red 2\"' setup-teams14.frayscene"
"$cli" metrics setup-teams14.frayscene -q > metrics.txt
check "metrics read it" "grep -q '^blue 4' metrics.txt"

# Bad parameters: refused at import, naming the field; nothing stored.
bad() {
  echo "$2" > bad.json
  expect_fail "$1" "$3" "$cli" setup "$p" import bad --spec bad.json -q
}
bad "depth 0" '{"kind": "graph-duel", "depth": 0}' "/depth: must be an integer from 1 to 64"
bad "style" '{"kind": "graph-duel", "style": "brawler"}' "/style: 'brawler' is not one of general, infighter, outboxer"
bad "typo" '{"kind": "graph-duel", "dept": 3}' "/dept: unknown parameter of a graph-duel setup"
bad "team size" '{"kind": "graph-teams", "red": 0}' "/red: must be an integer from 1 to 5000"
bad "duration" '{"kind": "graph-teams", "duration": -1}' "/duration: must be in (0, 3600]"
bad "opponent" '{"kind": "graph-duel", "opponent": "tree"}' "/opponent: 'tree' is not one of graph, static"
bad "carry weight" '{"kind": "graph-carry", "path": "circle:3", "weights": {"w_d": -1}}' "/weights/w_d: must be a finite number >= 0"
bad "carry path" '{"kind": "graph-carry", "path": "square:3"}' "/path: 'square:3' is not circle:R"
bad "carry without path" '{"kind": "graph-carry"}' "the box has no path"
check "nothing stored" "! grep -q '\"bad\"' '$p'"
expect_fail "compose refuses" "is a graph-duel setup: run it with simulate, not compose" "$cli" compose "$p" --setup gduel -o x.frayscene -q
"$cli" setup "$p" show gduel > show.txt
check "show says simulate" "grep -q 'run with fray-cli simulate' show.txt"

# graph-carry on the carry set: a circle of 3 m = igraph play --path circle:3.
"$cli" demo-library "$tmp/carry" --set carry --minutes 1 > /dev/null 2>&1
c=$tmp/carry/demo.frayproj
echo '{"kind": "graph-carry", "duration": 10, "carry_states": 3000, "path": "circle:3"}' > carry.json
"$cli" setup "$c" import gcarry --spec carry.json -q > /dev/null
"$cli" simulate "$c" --setup gcarry -o setup-carry.frayscene -q > carry.txt
check "carry summary" "grep -q 'path error mean' carry.txt"
"$cli" igraph play "$c" --kind carry --path circle:3 --seconds 10 --carry-states 3000 -o play-carry.frayscene -q > /dev/null
check "graph-carry = igraph play" "cmp -s setup-carry.frayscene play-carry.frayscene"
# A polyline path.
echo '{"kind": "graph-carry", "duration": 8, "carry_states": 3000, "path": {"loop": false, "points": [[0, 0], [2, 0], [2, 2]]}}' > line.json
"$cli" setup "$c" import gline --spec line.json -q > /dev/null
"$cli" simulate "$c" --setup gline -o setup-line.frayscene -q > /dev/null
check "polyline path" "grep -q '\"body\": \"box\"' setup-line.frayscene"
# With a carry graph file beside the project (built with the setup's size) the
# setup reads it, as igraph play does, and both give the same bytes again.
"$cli" igraph build "$c" --kind carry --max-states 3000 -q > /dev/null
"$cli" simulate "$c" --setup gcarry -o setup-carry-file.frayscene -q > carry-file.txt
check "carry graph read from the file" "grep -q 'graph: demo.frayproj.carry.igraph' carry-file.txt"
"$cli" igraph play "$c" --kind carry --path circle:3 --seconds 10 -o play-carry-file.frayscene -q > /dev/null
check "graph-carry with the file = igraph play with the file" "cmp -s setup-carry-file.frayscene play-carry-file.frayscene"
echo "cli_igraph_setup: ok"
