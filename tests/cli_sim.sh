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

# ---- Issue 21: validation of specs, scenes and flags (each failed before) --
expect_refused() {
  local name=$1 text=$2; shift 2
  local rc=0
  "$@" > /dev/null 2> "$tmp/err.txt" || rc=$?
  if [[ $rc == 0 || $rc -ge 124 ]]; then echo "FAIL: $name: exit code $rc"; exit 1; fi
  check "$name: message" "grep -q -- \"$text\" '$tmp/err.txt'"
}
# Item 1: a scene whose spec is nested 100,000 levels deep crashed metrics.
python3 - "$tmp/duel.frayscene" "$tmp/deep.frayscene" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["spec"] = "DEEP"
open(sys.argv[2], "w").write(json.dumps(doc).replace('"DEEP"', "[" * 100000 + "]" * 100000))
PY
expect_fail "deep scene" "deep.frayscene:1:.*nested deeper than 64 levels" "$cli" metrics "$tmp/deep.frayscene" -q
# Item 8: unbounded scene durations ("-2147483647 frames").
sed 's/"duration": [0-9.e+]*/"duration": 1e8/' "$tmp/duel.frayscene" > "$tmp/long.frayscene"
expect_fail "scene duration" "long.frayscene: /duration: must be a positive number of seconds, at most 3600" \
  "$cli" metrics "$tmp/long.frayscene" -q
# Item 9: invalid compose JSON was reported as a missing patch library.
printf '{"kind": "duel",\n "duration": }\n' > "$tmp/bad_compose.json"
expect_fail "compose spec syntax" "bad_compose.json:2:[0-9]*: not valid JSON" \
  "$cli" compose "$p" --spec "$tmp/bad_compose.json" --out "$tmp/c.frayscene" -q
# Item 13: spec syntax errors give the line and column.
printf '{"duration": 5,\n "characters": [{"name": "a",}]}\n' > "$tmp/bad5.json"
expect_fail "spec syntax" "bad5.json:2:[0-9]*: not valid JSON" \
  "$cli" simulate "$p" --spec "$tmp/bad5.json" --out "$tmp/bad5.frayscene" -q
# Item 12: a checkpoint time of -1, a negative weight, render flags.
echo '{"duration": 5, "characters": [{"name": "a", "path": [{"x": 1, "z": 0, "time": -1}]}]}' > "$tmp/bad6.json"
expect_fail "checkpoint time" "bad6.json: /characters/0/path/0/time: must be between 0 and 3600" \
  "$cli" simulate "$p" --spec "$tmp/bad6.json" --out "$tmp/bad6.frayscene" -q
expect_fail "negative weight" "w_r: must be between 0 and 1e6" "$cli" presets "$p" set brawler w_r=-5
# Item 10: a description that is not UTF-8 ended in type_error.316.
expect_fail "non-UTF-8 description" "must be UTF-8 text" "$cli" presets "$p" set brawler --description $'caf\xe9'
check "project untouched by refused presets" "cmp -s '$p' '$tmp/before.frayproj'"
expect_refused "render --yaw nan" "--yaw: nan must be a finite number" "$cli" render "$tmp/duel.frayscene" --out "$tmp/frames" --yaw=nan
for v in 0 3; do
  expect_refused "render --msaa $v" "--msaa: $v not in" "$cli" render "$tmp/duel.frayscene" --out "$tmp/frames" --msaa=$v
done
check "no frames from refused renders" "[ ! -e '$tmp/frames' ]"
echo "PASS"
