#!/usr/bin/env bash
# fray-cli render --rig end to end on lavapipe: a character exported by
# `fray-cli export` (GLB and FBX) is drawn instead of the capsules, for motion
# files and for a scene, with validation on and no messages; a broken rig with
# a scene is one line and exit code 1. (Broken rig files of every kind:
# cli_render_rig_errors.sh.)
# Usage: cli_render_rig.sh FRAY_CLI DEMO_LIBRARY_DIR
set -uo pipefail
cli=$1 lib=$2
. "$(dirname "$0")/../cli_lib.sh"
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
motion="$lib/walking.bvh"
[[ -f $motion && -f $lib/demo.frayproj ]] || { echo "FAIL: the demo library is missing in $lib (the build writes it)"; exit 1; }

# Rigs: a two-boxer scene exported as GLB and FBX (their skeleton is the demo actor's).
duel_spec 2 1 1 > "$tmp/duel.json"
"$cli" simulate "$lib/demo.frayproj" --spec "$tmp/duel.json" --out "$tmp/duel.frayscene" -q > /dev/null 2>&1 ||
  { echo "FAIL: simulate"; exit 1; }
for format in glb fbx; do
  "$cli" export "$tmp/duel.frayscene" --format $format --out "$tmp/rig" -q > /dev/null 2>&1 || bad "export $format"
done

# A motion with the GLB rig: the first of its two characters is used, with a warning.
if ! "$cli" render "$motion" --frames 0:30:30 --size 96x64 --rig "$tmp/rig/duel.glb" --validate --out "$tmp/glb" \
     > "$tmp/glb.out" 2> "$tmp/glb.err"; then
  bad "render with the GLB rig failed: $(cat "$tmp/glb.err")"
fi
[[ -s $tmp/glb/frame_000000.png && -s $tmp/glb/frame_000030.png ]] || bad "GLB rig: frames missing"
grep -q "warning: $tmp/rig/duel.glb: the file has skinned meshes on 2 armatures; only the first ('red') is used" "$tmp/glb.err" ||
  bad "GLB rig: expected the armature warning, got: $(cat "$tmp/glb.err")"
grep -qi "validation" "$tmp/glb.err" && bad "GLB rig: validation messages: $(cat "$tmp/glb.err")"

# A scene with the FBX rig (centimetres, joints named red_Hips, ...), fast quality.
if ! "$cli" render "$tmp/duel.frayscene" --frames 0:30:30 --size 96x64 --fast --rig "$tmp/rig/duel.fbx" --validate --quiet \
     --out "$tmp/fbx" > /dev/null 2> "$tmp/fbx.err"; then
  bad "scene with the FBX rig failed: $(cat "$tmp/fbx.err")"
fi
[[ -s $tmp/fbx/frame_000030.png ]] || bad "FBX rig: frames missing"
# The FBX holds two characters too; --quiet keeps that warning off stderr.
[[ -s $tmp/fbx.err ]] && bad "--quiet printed: $(cat "$tmp/fbx.err")"

# A broken rig with a scene: the same one-line error, after the scene loaded.
rc=0
head -c 50000 "$tmp/rig/duel.glb" > "$tmp/cut.glb"
"$cli" render "$tmp/duel.frayscene" --quiet --rig "$tmp/cut.glb" --frames 0 --out "$tmp/x" > /dev/null 2> "$tmp/err.log" || rc=$?
(( rc == 1 )) || bad "scene with a broken rig: exit code $rc"
grep -qF "fray-cli: $tmp/cut.glb: Assimp cannot read the file: " "$tmp/err.log" && (( $(grep -c "" "$tmp/err.log") == 1 )) ||
  bad "scene with a broken rig: $(cat "$tmp/err.log")"
[[ -e $tmp/x ]] && bad "scene with a broken rig: the output folder was created"

if (( fails > 0 )); then echo "$fails failure(s)"; exit 1; fi
echo "cli_render_rig: all checks passed"
