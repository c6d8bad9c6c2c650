#!/usr/bin/env bash
# Mixed skeletons and rigs through fray-cli: `project new` on takes of three
# sources prints the mapping report and the graph builds across them;
# `export --rig` / `--root-motion` on a demo duel; bad input (a take without
# feet, a rig without feet, an unknown root-motion mode) is a one-line error
# naming what is missing.
# Usage: cli_retarget.sh FRAY_CLI SHARED_DIR
set -eu
cli=$1 shared=$2/mocap
. "$(dirname "$0")/cli_lib.sh"

"$cli" project new "$tmp/mix.frayproj" --import "$shared/cmu135_karate/oiduki001.bvh" \
  "$shared/lafan1/push1_subject2.bvh" "$shared/bandai/dataset-1_walk_normal_001.bvh" > "$tmp/new.txt" 2> /dev/null
check "two takes retargeted, reported" "[ \$(grep -c '^retargeted .* onto the project skeleton' '$tmp/new.txt') -eq 2 ]"
check "the report maps the feet" "grep -q 'leftFoot LeftFoot->lfoot' '$tmp/new.txt'"
check "the report says what was dropped" "grep -q 'dropped (source joints that drive nothing)' '$tmp/new.txt'"
"$cli" contacts "$tmp/mix.frayproj" -q > /dev/null
"$cli" segment "$tmp/mix.frayproj" -q > /dev/null
"$cli" graph "$tmp/mix.frayproj" -q > "$tmp/graph.txt"
check "one motion graph across the sources" "grep -q 'largest strongly connected component' '$tmp/graph.txt'"

# A take whose legs have no names a convention knows.
sed -e 's/LeftFoot/BoneA/g; s/RightFoot/BoneB/g; s/LeftToe/BoneC/g; s/RightToe/BoneD/g; s/LeftLeg/BoneE/g; s/RightLeg/BoneF/g' \
    -e 's/LeftUpLeg/BoneG/g; s/RightUpLeg/BoneH/g' "$shared/lafan1/walk4_subject1.bvh" > "$tmp/odd.bvh"
if "$cli" project new "$tmp/bad.frayproj" --import "$shared/cmu135_karate/oiduki001.bvh" "$tmp/odd.bvh" \
  > /dev/null 2> "$tmp/err.txt"; then echo "FAIL: take without feet: accepted"; exit 1; fi
check "take without feet: what is missing" "grep -q 'odd.bvh: cannot retarget: no feet found (leftFoot, rightFoot' '$tmp/err.txt'"
check "take without feet: its joints" "grep -q 'its joints are Hips, BoneG' '$tmp/err.txt'"
check "nothing written for the refused project" "[ ! -f '$tmp/bad.frayproj' ]"

# export --rig onto the CMU base skeleton (FBX, bones only), root on the floor.
project=$tmp/lib/demo.frayproj
"$cli" demo-library "$tmp/lib" --minutes 2 > /dev/null 2>&1
duel_spec 4 1 1 > "$tmp/duel.json"
"$cli" simulate "$project" --spec "$tmp/duel.json" --out "$tmp/duel.frayscene" -q > /dev/null
"$cli" export "$tmp/duel.frayscene" --format bvh --out "$tmp/out" --rig "$shared/cmu_fbx/Base.fbx" --root-motion floor \
  > "$tmp/export.txt" 2> "$tmp/export_err.txt"
check "no skin: said" "grep -q 'no mesh (a skeleton only)' '$tmp/export_err.txt'"
check "mapping per character" "[ \$(grep -c '^note: retargeted character' '$tmp/export.txt') -eq 2 ]"
check "rig joint names and root bone in the BVH" "grep -q 'ROOT root' '$tmp/out/duel_red.bvh' && grep -q 'JOINT Neo_Hips' '$tmp/out/duel_red.bvh'"
printf 'HIERARCHY\nROOT Hips\n{\n OFFSET 0 100 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n JOINT Head\n {\n  OFFSET 0 60 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 20 0\n  }\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.033\n0 100 0 0 0 0 0 0 0\n' > "$tmp/nofeet.bvh"
expect_fail "rig without feet" "nofeet.bvh: cannot retarget: no feet found" \
  "$cli" export "$tmp/duel.frayscene" --out "$tmp/out2" --rig "$tmp/nofeet.bvh" -q
expect_fail "unknown root motion" "expected none, floor or in-place" \
  "$cli" export "$tmp/duel.frayscene" --out "$tmp/out2" --root-motion sideways -q
echo "PASS"
