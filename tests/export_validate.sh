#!/usr/bin/env bash
# The demo duel (resources/demo/duel.json on the build's demo library)
# exported in every format: its BVH rotation channels continuous (no jump over
# 180 degrees between frames); where `blender` is on PATH,
# scripts/blender-import-check.py on every file (skipped with a message
# otherwise); then the Khronos glTF-Validator (scripts/validate-gltf.mjs) on
# the .gltf and .glb, and on the demo rat scene (a one-joint creature among
# people standing as looped idles) as .glb: no error and no warning. Without node or the validator the
# validator part is skipped (exit 77), unless REQUIRED is ON (the ci preset):
# then it fails.
# Usage: export_validate.sh FRAY_CLI DEMO_PROJECT SOURCE_DIR REQUIRED
set -eu
cli=$1 project=$2 repo=$3 required=$4
. "$(dirname "$0")/cli_lib.sh"

"$cli" simulate "$project" --spec "$repo/resources/demo/duel.json" --out "$tmp/duel.frayscene" -q > /dev/null
for f in gltf glb fbx bvh; do "$cli" export "$tmp/duel.frayscene" --format $f --out "$tmp/out" -q > /dev/null; done
for f in "$tmp"/out/duel_*.bvh; do
  check "$(basename "$f"): rotation channels continuous" "[ \$(awk -f '$repo/tests/export/bvh_jumps.awk' '$f') -eq 0 ]"
done
if command -v blender > /dev/null; then
  blender -b --factory-startup --python "$repo/scripts/blender-import-check.py" -- \
    "$tmp/out/duel.gltf" "$tmp/out/duel.glb" "$tmp/out/duel.fbx" "$tmp"/out/duel_*.bvh > "$tmp/blender.txt" 2>&1 ||
    { grep -E 'FAILED|Error|error' "$tmp/blender.txt" | head -20; echo "FAIL: blender-import-check.py"; exit 1; }
  grep -E '^/.*: ' "$tmp/blender.txt"
else
  echo "SKIP (Blender part only): blender is not installed; scripts/blender-import-check.py not run"
fi

validator=${GLTF_VALIDATOR_DIR:-$repo/build-tools/gltf-validator}
if ! command -v node > /dev/null || [ ! -f "$validator/node_modules/gltf-validator/package.json" ]; then
  msg="node or the glTF-Validator is missing (looked in $validator; run scripts/install-gltf-validator.sh)"
  if [ "$required" = ON ]; then echo "FAIL: $msg"; exit 1; fi
  echo "SKIP: $msg"; exit 77
fi

sed 's/"crowd": [0-9]*/"crowd": 20/' "$repo/resources/demo/rat.json" > "$tmp/rat.json"
"$cli" compose "$project" --spec "$tmp/rat.json" --out "$tmp/rat.frayscene" -q > /dev/null
# Its bystanders stand as looped idles (scene version 2): the export plays them time round after time round.
check "the rat scene has looped idles" "grep -q '\"version\": 2' '$tmp/rat.frayscene' && grep -q '\"loop\": ' '$tmp/rat.frayscene'"
"$cli" export "$tmp/rat.frayscene" --format glb --out "$tmp/out" -q > /dev/null
GLTF_VALIDATOR_DIR=$validator node "$repo/scripts/validate-gltf.mjs" "$tmp/out/duel.gltf" "$tmp/out/duel.glb" "$tmp/out/rat.glb" | tee "$tmp/report.txt"
check "all three files validated" "[ \$(grep -c ': 0 errors, 0 warnings' '$tmp/report.txt') -eq 3 ]"
# The duel retargeted onto the CMU base skeleton (FBX, no mesh) with a root
# bone on the floor, as .gltf and .glb (export --rig, --root-motion).
base="$repo/../shared/mocap/cmu_fbx/Base.fbx"
if [ -f "$base" ]; then
  for f in gltf glb; do
    "$cli" export "$tmp/duel.frayscene" --format $f --out "$tmp/rig" --rig "$base" --root-motion floor -q > /dev/null
  done
  GLTF_VALIDATOR_DIR=$validator node "$repo/scripts/validate-gltf.mjs" "$tmp/rig/duel.gltf" "$tmp/rig/duel.glb" | tee "$tmp/rig.txt"
  check "both rig exports validated" "[ \$(grep -c ': 0 errors, 0 warnings' '$tmp/rig.txt') -eq 2 ]"
else
  echo "SKIP (rig part only): $base not found"
fi
# The validator must be able to fail here: a cubic-spline sampler with one
# output per key (it needs three) is an error.
sed '0,/"LINEAR"/s//"CUBICSPLINE"/' "$tmp/out/duel.gltf" > "$tmp/broken.gltf"
check "the edit broke something" "! cmp -s '$tmp/out/duel.gltf' '$tmp/broken.gltf'"
if GLTF_VALIDATOR_DIR=$validator node "$repo/scripts/validate-gltf.mjs" "$tmp/broken.gltf" > "$tmp/broken.txt"; then
  echo "FAIL: the validator accepted a broken file"; exit 1
fi
echo "PASS"
