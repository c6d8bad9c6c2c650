#!/usr/bin/env bash
# Tree expansion from the command line on a small demo project: simulate a
# duel, read its metrics, the same seed gives the same bytes, presets edit the
# project; and bad input: unknown annotation, no usable action, negative
# duration, a scene whose actions changed, a non-scene output file. Each is a
# one-line error that leaves the files untouched.
set -eu
cli=$1
. "$(dirname "$0")/cli_lib.sh"

"$cli" demo-library "$tmp/lib" --minutes 3 > /dev/null 2>&1
p=$tmp/lib/demo.frayproj
duel_spec 8 3 2 > "$tmp/duel.json"
"$cli" simulate "$p" --spec "$tmp/duel.json" --out "$tmp/duel.frayscene" 2> "$tmp/progress.txt" > "$tmp/sim.txt"
check "progress on stderr" "grep -q 'simulate 100%' '$tmp/progress.txt'"
check "summary" "grep -q 'pruned' '$tmp/sim.txt'"
check "scene written" "grep -q '\"format\": \"fray-scene\"' '$tmp/duel.frayscene'"
check "project path relative" "grep -q '\"project\": \"lib/demo.frayproj\"' '$tmp/duel.frayscene'"
"$cli" simulate "$p" --spec "$tmp/duel.json" --out "$tmp/again.frayscene" -q > /dev/null
check "same seed, same bytes" "cmp -s '$tmp/duel.frayscene' '$tmp/again.frayscene'"
"$cli" metrics "$tmp/duel.frayscene" -q > "$tmp/metrics.txt"
check "metrics per character" "grep -q '^red' '$tmp/metrics.txt' && grep -q '^blue' '$tmp/metrics.txt'"
"$cli" metrics "$tmp/duel.frayscene" --json -q > "$tmp/metrics.json"
check "metrics json" "grep -q '\"mean_opponent_distance\"' '$tmp/metrics.json' && grep -q '\"foot_skate_mean_cm\"' '$tmp/metrics.json'"

# Presets live in the project.
"$cli" presets "$p" set infighter r_d=0.45 > /dev/null
"$cli" presets "$p" show infighter > "$tmp/preset.txt"
check "preset stored" "grep -q '\"r_d\":0.45' '$tmp/preset.txt'"
expect_fail "bad weight" "unknown weight" "$cli" presets "$p" set infighter w_tehta=1
"$cli" presets "$p" remove infighter > /dev/null

# Bad specs: one line naming the file and the field; nothing written.
cp "$p" "$tmp/before.frayproj"
sed 's/"@kick"/"@kik"/' "$tmp/duel.json" > "$tmp/bad1.json"
expect_fail "unknown annotation" "bad1.json: /characters/0/actions/1: unknown annotation 'kik'" \
  "$cli" simulate "$p" --spec "$tmp/bad1.json" --out "$tmp/bad1.frayscene" -q
check "no scene from a bad spec" "[ ! -e '$tmp/bad1.frayscene' ]"
echo '{"duration": 5, "characters": [{"name": "a", "actions": ["@falling"]}]}' > "$tmp/bad2.json"
expect_fail "no usable action" "character 'a' has no usable action" \
  "$cli" simulate "$p" --spec "$tmp/bad2.json" --out "$tmp/bad2.frayscene" -q
echo '{"duration": -1, "characters": [{"name": "a"}]}' > "$tmp/bad3.json"
expect_fail "negative duration" "bad3.json: /duration: must be a positive" \
  "$cli" simulate "$p" --spec "$tmp/bad3.json" --out "$tmp/bad3.frayscene" -q
echo '{"duration": 5, "characters": [{"name": "a", "path": []}]}' > "$tmp/bad4.json"
expect_fail "empty path" "bad4.json: /characters/0/path: is empty" \
  "$cli" simulate "$p" --spec "$tmp/bad4.json" --out "$tmp/bad4.frayscene" -q
echo "my notes" > "$tmp/notes.txt"
expect_fail "never overwrite other files" "refusing to overwrite" \
  "$cli" simulate "$p" --spec "$tmp/duel.json" --out "$tmp/notes.txt" -q
check "notes untouched" "[ \"\$(cat '$tmp/notes.txt')\" = 'my notes' ]"
check "project untouched by failures" "cmp -s '$p' '$tmp/before.frayproj'"

# A scene whose actions were re-cut is refused with the path of the action.
sed 's/"first": \([0-9]*\)/"first": 9\1/' "$tmp/duel.frayscene" > "$tmp/stale.frayscene"
expect_fail "stale scene" "is not in the project any more" "$cli" metrics "$tmp/stale.frayscene" -q
echo "PASS"
