#!/usr/bin/env bash
# `fray-cli metrics --posture`: the physics posture metrics of a planned duel
# on a small demo project, the same bytes twice, and a bad mode named.
set -eu
cli=$1
. "$(dirname "$0")/../cli_lib.sh"

"$cli" demo-library "$tmp/lib" --minutes 3 > /dev/null 2>&1
duel_spec 6 3 2 > "$tmp/duel.json"
"$cli" simulate "$tmp/lib/demo.frayproj" --spec "$tmp/duel.json" --out "$tmp/duel.frayscene" -q > /dev/null
"$cli" metrics "$tmp/duel.frayscene" --posture physics --json -q > "$tmp/physics.json"
check "posture json" "grep -q '\"foot_skate_max_cm\"' '$tmp/physics.json' && grep -q '\"penetration_max_cm\"' '$tmp/physics.json' && grep -q '\"deviation_mean_cm\"' '$tmp/physics.json'"
check "only the posture metrics with --json" "! grep -q '\"hit_rate\"' '$tmp/physics.json'"
"$cli" metrics "$tmp/duel.frayscene" --posture physics --json -q > "$tmp/again.json"
check "same scene, same bytes" "cmp -s '$tmp/physics.json' '$tmp/again.json'"
"$cli" metrics "$tmp/duel.frayscene" --posture kinematic -q > "$tmp/kinematic.txt"
check "text: scene metrics then posture" "grep -q '^scene:' '$tmp/kinematic.txt' && grep -q '^posture:' '$tmp/kinematic.txt'"
expect_fail "bad mode" "--posture: 'ragdoll' is not kinematic or physics" "$cli" metrics "$tmp/duel.frayscene" --posture ragdoll -q
echo "cli posture: ok"
