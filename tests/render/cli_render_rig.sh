#!/usr/bin/env bash
# fray-cli render --rig end to end on lavapipe: a character exported by
# `fray-cli export` (GLB and FBX) is drawn instead of the capsules, for motion
# files and for a scene, with validation on and no messages; a broken rig is
# one clear line on stderr, a non-zero exit code and no crash, before any
# frame is written.
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
# --quiet keeps warnings off stderr.
"$cli" render "$motion" --frames 0 --size 96x64 --rig "$tmp/rig/duel.glb" --quiet --out "$tmp/quiet" > /dev/null 2> "$tmp/quiet.err" ||
  bad "quiet render failed"
[[ -s $tmp/quiet.err ]] && bad "--quiet printed: $(cat "$tmp/quiet.err")"

# A scene with the FBX rig (centimetres, joints named red_Hips, ...), fast quality.
if ! "$cli" render "$tmp/duel.frayscene" --frames 0:30:30 --size 96x64 --fast --rig "$tmp/rig/duel.fbx" --validate --quiet \
     --out "$tmp/fbx" > /dev/null 2> "$tmp/fbx.err"; then
  bad "scene with the FBX rig failed: $(cat "$tmp/fbx.err")"
fi
[[ -s $tmp/fbx/frame_000030.png ]] || bad "FBX rig: frames missing"

# Broken rigs: exit code 1..127 (no crash), exactly one "fray-cli:" line naming the file and the problem, no frames.
expect_error() {
  local pattern=$1 rig=$2; shift 2
  local rc=0
  rm -rf "$tmp/x"
  "$cli" render "$@" --rig "$rig" --frames 0 --size 64x48 --out "$tmp/x" > /dev/null 2> "$tmp/err.log" || rc=$?
  if (( rc == 0 || rc >= 128 )); then bad "exit code $rc for --rig $rig"; fi
  grep -qF -- "$rig: $pattern" "$tmp/err.log" || bad "expected '$rig: $pattern' -- got: $(cat "$tmp/err.log")"
  (( $(grep -c "" "$tmp/err.log") == 1 )) || bad "expected one line for --rig $rig -- got: $(cat "$tmp/err.log")"
  [[ -e $tmp/x ]] && bad "--rig $rig: the output folder was created before the rig was checked"
}
head -c 50000 "$tmp/rig/duel.glb" > "$tmp/cut.glb"
echo "not a rig" > "$tmp/notes.glb"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/triangle.obj"
expect_error "Assimp cannot read the file: " "$tmp/cut.glb" "$motion"
expect_error "Assimp cannot read the file: " "$tmp/notes.glb" "$motion"
expect_error "file not found" "$tmp/missing.glb" "$motion"
expect_error "no mesh in the file" "$motion" "$motion"
expect_error "no skinned mesh: none of the file's 1 meshes has bones" "$tmp/triangle.obj" "$motion"
expect_error "Assimp cannot read the file: " "$tmp/cut.glb" "$tmp/duel.frayscene" --quiet

if (( fails > 0 )); then echo "$fails failure(s)"; exit 1; fi
echo "cli_render_rig: all checks passed"
