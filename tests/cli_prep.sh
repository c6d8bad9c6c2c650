#!/usr/bin/env bash
# The data-preparation verbs end to end on a small demo library: project new,
# contacts (SVM from labels, then from the cache), segment, actions, graph,
# combos; and bad input: missing motion file, corrupt project, labels past
# the end of a motion, each a one-line error that leaves the files untouched.
set -eu
cli=$1
. "$(dirname "$0")/cli_lib.sh"

"$cli" demo-library "$tmp/lib" --minutes 2 > /dev/null 2>&1
check "demo project written" "[ -f '$tmp/lib/demo.frayproj' ]"
check "labels written" "head -1 '$tmp/lib/contact_labels.csv' | grep -q '^motion,first_frame,last_frame,left,right'"

p=$tmp/run/p.frayproj
mkdir -p "$tmp/run"
"$cli" project new "$p" --import "$tmp"/lib/*.bvh > /dev/null 2>&1
check "paths are relative" "grep -q '\"path\": \"../lib/walking.bvh\"' '$p'"
expect_fail "no silent overwrite" "already exists" "$cli" project new "$p" --import "$tmp/lib/walking.bvh"

# Labels that name only the motions of this small library.
grep -E '^(motion|walking|shadowbox_energetic|running_around|falls),' "$tmp/lib/contact_labels.csv" > "$tmp/labels.csv"
"$cli" contacts "$p" --train "$tmp/labels.csv" -q > "$tmp/contacts.txt"
check "svm trained" "grep -q 'leave-one-out accuracy' '$tmp/contacts.txt'"
"$cli" contacts "$p" -q > "$tmp/contacts2.txt"
check "second run from the cache" "grep -q '(cached)' '$tmp/contacts2.txt'"
"$cli" segment "$p" -q > "$tmp/segment.txt"
check "segmented" "grep -q '^total: [0-9]* actions' '$tmp/segment.txt'"
"$cli" actions "$p" --json > "$tmp/actions.json"
check "actions json" "grep -q '\"first_frame\"' '$tmp/actions.json'"
"$cli" graph "$p" -q > "$tmp/graph.txt"
check "graph stats" "grep -q 'largest strongly connected component' '$tmp/graph.txt'"
"$cli" graph "$p" -q > "$tmp/graph2.txt"
check "second graph from the cache" "grep -q '(cached)' '$tmp/graph2.txt'"
check "same graph from the cache" "[ \"\$(sed 's/ (cached)//' '$tmp/graph2.txt')\" = \"\$(cat '$tmp/graph.txt')\" ]"
"$cli" combos "$p" set sway_back @punch 1.5
"$cli" combos "$p" export "$tmp/combos.csv" > /dev/null
check "combos exported" "grep -q '^sway_back,@punch,1.5' '$tmp/combos.csv'"
"$cli" combos "$p" remove sway_back @punch
"$cli" combos "$p" import "$tmp/combos.csv" > /dev/null
check "combos imported" "$cli combos '$p' list | grep -q 'sway_back'"

# Bad input leaves the project byte-identical.
cp "$p" "$tmp/before.frayproj"
printf 'motion,first_frame,last_frame,left,right\nwalking,10,999999,1,0\n' > "$tmp/bad_labels.csv"
expect_fail "labels past the end" "bad_labels.csv:2: last_frame: frame 999999 is past the end of \\\"walking\\\"" \
  "$cli" contacts "$p" --train "$tmp/bad_labels.csv" -q
check "project untouched (labels)" "cmp -s '$p' '$tmp/before.frayproj'"

mv "$tmp/lib/walking.bvh" "$tmp/lib/walking.moved"
expect_fail "missing motion file" "/motions/.*/path: motion file .*walking.bvh' does not exist" "$cli" segment "$p" -q
check "project untouched (missing motion)" "cmp -s '$p' '$tmp/before.frayproj'"
mv "$tmp/lib/walking.moved" "$tmp/lib/walking.bvh"

head -c 300 "$tmp/before.frayproj" > "$p"
cp "$p" "$tmp/corrupt.frayproj"
expect_fail "corrupt project" "p.frayproj:.*not valid JSON" "$cli" segment "$p" -q
check "corrupt project untouched" "cmp -s '$p' '$tmp/corrupt.frayproj'"
expect_fail "missing project" "cannot open the project file" "$cli" graph "$tmp/none.frayproj" -q
echo "cli_prep: ok"
