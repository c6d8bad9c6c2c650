#!/usr/bin/env bash
# `fray-cli metrics --posture`: the physics posture metrics of a planned duel
# on a small demo project, the same bytes twice, and a bad mode named;
# `export --posture physics` writes the same bytes twice and differs from the
# kinematic export; `render --posture physics` draws the scene.
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
# export: physics twice, byte-identical; kinematic differs.
"$cli" export "$tmp/duel.frayscene" --format glb --out "$tmp/phys1" --posture physics -q > "$tmp/export.txt"
check "export says physics" "grep -q '^posture: physics' '$tmp/export.txt'"
"$cli" export "$tmp/duel.frayscene" --format glb --out "$tmp/phys2" --posture physics -q > /dev/null
"$cli" export "$tmp/duel.frayscene" --format glb --out "$tmp/kin" --posture kinematic -q > /dev/null
"$cli" export "$tmp/duel.frayscene" --format glb --out "$tmp/plain" -q > /dev/null
check "physics export: same bytes twice" "cmp -s '$tmp/phys1/duel.glb' '$tmp/phys2/duel.glb'"
check "kinematic is the default" "cmp -s '$tmp/kin/duel.glb' '$tmp/plain/duel.glb'"
check "physics differs from kinematic" "! cmp -s '$tmp/phys1/duel.glb' '$tmp/kin/duel.glb'"
"$cli" export "$tmp/duel.frayscene" --format bvh --out "$tmp/bvh" --posture physics -q > /dev/null
check "physics BVH finite" "! grep -qi 'nan\\|inf' '$tmp'/bvh/*.bvh"
expect_fail "export: bad mode" "--posture: 'ragdoll' is not kinematic or physics" "$cli" export "$tmp/duel.frayscene" --out "$tmp/bad" --posture ragdoll -q
# render: one frame with physics.
"$cli" render "$tmp/duel.frayscene" --out "$tmp/frames" --frames 60 --size 160x90 --fast --posture physics --quiet > /dev/null
check "render: a frame" "[ -s '$tmp/frames/scene_000060.png' ] || ls '$tmp/frames' | grep -q png"
expect_fail "render: bad mode" "--posture: 'ragdoll' is not kinematic or physics" "$cli" render "$tmp/duel.frayscene" --out "$tmp/frames" --posture ragdoll --quiet
# --hand-pins: a small luggage chain, the porters' hands pinned to the bag
# (posture::Options::handPins) change the physics poses; only with physics.
"$cli" patches generate "$tmp/lib/demo.frayproj" --pattern carry-hand-receive-carry --out "$tmp/carry.patches" -q > /dev/null
echo '{"kind": "luggage", "porters": 3, "handoffs": 2, "seed": 1, "duration": 60}' > "$tmp/luggage.json"
"$cli" compose "$tmp/lib/demo.frayproj" --patches "$tmp/carry.patches" --spec "$tmp/luggage.json" --out "$tmp/luggage.frayscene" -q > /dev/null 2>&1
"$cli" metrics "$tmp/luggage.frayscene" --posture physics --json -q > "$tmp/free.json"
"$cli" metrics "$tmp/luggage.frayscene" --posture physics --hand-pins --json -q > "$tmp/pinned.json"
"$cli" metrics "$tmp/luggage.frayscene" --posture physics --hand-pins --json -q > "$tmp/pinned2.json"
check "hand pins change the physics poses" "! cmp -s '$tmp/free.json' '$tmp/pinned.json'"
check "hand pins: same bytes twice" "cmp -s '$tmp/pinned.json' '$tmp/pinned2.json'"
expect_fail "hand pins need physics" "--hand-pins: only with --posture physics" "$cli" metrics "$tmp/luggage.frayscene" --posture kinematic --hand-pins -q
expect_fail "export: hand pins need physics" "--hand-pins: only with --posture physics" "$cli" export "$tmp/luggage.frayscene" --out "$tmp/bad" --hand-pins -q
echo "cli posture: ok"
