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

# ---- Issue 21: file safety and validation (each check failed before) ------
p=$tmp/run/p.frayproj
cp "$tmp/before.frayproj" "$p"
# A command refused by CLI11 or by fray-cli: non-zero exit (no crash) and TEXT on stderr.
expect_refused() {
  local name=$1 text=$2; shift 2
  local rc=0
  "$@" > /dev/null 2> "$tmp/err.txt" || rc=$?
  if [[ $rc == 0 || $rc -ge 124 ]]; then echo "FAIL: $name: exit code $rc"; exit 1; fi
  check "$name: message" "grep -q -- \"$text\" '$tmp/err.txt'"
}
# Item 1: a project nested 100,000 levels deep crashed every verb.
python3 -c "import sys; sys.stdout.write('{\"format\": \"fray-project\", \"version\": 1, \"motions\": [], \"paintings\": ' + '['*100000 + ']'*100000 + '}')" > "$tmp/deep.frayproj"
expect_fail "deep project" "deep.frayproj:1:.*nested deeper than 64 levels" "$cli" actions "$tmp/deep.frayproj"
# Item 4: non-finite or missing suitabilities were stored (as null or 0).
for v in nan inf 1e999; do
  expect_fail "combos set $v" "VALUE .$v. must be a finite number" "$cli" combos "$p" set jab @block "$v"
done
expect_fail "combos set without a value" "the suitability is missing" "$cli" combos "$p" set jab @block
# Item 12: records naming annotations outside the vocabulary.
expect_fail "unknown annotation" "mine: @flyingkick is not in the project vocabulary" "$cli" combos "$p" set @flyingkick @block 1
check "project untouched (bad combos)" "cmp -s '$p' '$tmp/before.frayproj'"
"$cli" actions "$p" > /dev/null
# Item 5: outputs that are the project or one of its captures.
expect_fail "timeline onto the project" "is the project file; refusing to overwrite it" "$cli" timeline "$p" walking -o "$p"
cp "$tmp/lib/walking.bvh" "$tmp/walking.before"
expect_fail "combos export onto a capture" "is the capture of motion" "$cli" combos "$p" export "$tmp/lib/walking.bvh"
check "project untouched (outputs)" "cmp -s '$p' '$tmp/before.frayproj'"
check "capture untouched" "cmp -s '$tmp/lib/walking.bvh' '$tmp/walking.before'"
# Item 6: a flipped bit in the cache was trusted ("(cached)").
"$cli" graph "$p" -q > "$tmp/graph3.txt"
python3 -c "import sys; b = bytearray(open(sys.argv[1], 'rb').read()); b[60] ^= 4; open(sys.argv[1], 'wb').write(b)" "$p.cache"
"$cli" graph "$p" -q > "$tmp/graph4.txt" 2> "$tmp/graph4.err"
check "damaged cache not trusted" "! grep -q '(cached)' '$tmp/graph4.txt'"
check "damaged cache reported" "grep -q 'checksum mismatch.*rebuilding' '$tmp/graph4.err'"
check "rebuilt graph equals the cached one" "[ \"\$(sed 's/ (cached)//' '$tmp/graph3.txt')\" = \"\$(cat '$tmp/graph4.txt')\" ]"
# Item 7: saving through a link kept neither the link nor the mode.
chmod 600 "$p"
ln -s run/p.frayproj "$tmp/link.frayproj"
"$cli" combos "$tmp/link.frayproj" set sway_back @punch 2.5
check "link still a link" "[ -L '$tmp/link.frayproj' ]"
check "edit reached the target" "grep -q '\"suitability\": 2.5' '$p'"
check "mode kept" "[ \$(stat -c %a '$p') = 600 ]"
chmod 644 "$p"
# Item 12: flags that took 0, negatives and nan.
for v in 0 -3 nan; do
  expect_refused "segment --threshold-factor $v" "--threshold-factor: $v must be a finite number" "$cli" segment "$p" -q --threshold-factor=$v
  expect_refused "graph --threshold $v" "--threshold: $v must be a finite number" "$cli" graph "$p" -q --threshold=$v
done
# Item 10: frame rates that ran out of memory or wrote hundreds of MB.
for v in nan 1e9 1e6 20000; do
  expect_refused "convert --fps $v" "must be a finite number in (0, 1000]" "$cli" convert "$tmp/lib/walking.bvh" "$tmp/c.bvh" --fps=$v
done
check "no output from refused converts" "[ ! -e '$tmp/c.bvh' ]"
# Item 13: a device as a motion, a byte-order mark, binary CSV content.
sed 's#"../lib/walking.bvh"#"/dev/zero"#' "$p" > "$tmp/run/zero.frayproj"
expect_fail "device as a motion" "'/dev/zero' is not a regular file" "$cli" segment "$tmp/run/zero.frayproj" -q
printf '\xef\xbb\xbfmine,theirs,suitability\nsway_back,@kick,3\n' > "$tmp/bom.csv"
"$cli" combos "$p" import "$tmp/bom.csv" > /dev/null
check "BOM CSV imported" "$cli combos '$p' list | grep -q '@kick'"
printf 'mine,theirs,suitability\n\x1b[2Jx\xff,@kick,3\n' > "$tmp/esc.csv"
expect_fail "binary CSV" "esc.csv:2: mine" "$cli" combos "$p" import "$tmp/esc.csv"
check "no terminal escapes echoed" "! grep -q \$'\\x1b' '$tmp/err.txt'"
# Item 10: names that are not UTF-8 ended in type_error.316.
python3 -c "import sys; b = open(sys.argv[1], 'rb').read().replace(b'JOINT Spine2', b'JOINT Spin\xe92'); open(sys.argv[2], 'wb').write(b)" \
  "$tmp/lib/walking.bvh" "$tmp/latin1.bvh"
"$cli" info "$tmp/latin1.bvh" --json > "$tmp/latin1.json"
check "Latin-1 joint name as U+FFFD" "grep -q \$'Spin\\xef\\xbf\\xbd2' '$tmp/latin1.json'"
cp "$tmp/lib/walking.bvh" "$tmp/caf"$'\xe9'".bvh"
expect_fail "Latin-1 file name" "the file name is not UTF-8 text" "$cli" project new "$tmp/latin1.frayproj" --import "$tmp/caf"$'\xe9'".bvh"
check "no project from a refused import" "[ ! -e '$tmp/latin1.frayproj' ]"
echo "cli_prep: ok"
