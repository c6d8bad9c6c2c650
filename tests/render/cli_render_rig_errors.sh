#!/usr/bin/env bash
# fray-cli render --rig with broken rig files: exit code 1..127 (no crash),
# exactly one "fray-cli:" line naming the file and the problem, and no output
# folder (the rig is checked before any Vulkan work). Motion input only, so it
# stays fast under ASan; the successful cases are in cli_render_rig.sh.
# Usage: cli_render_rig_errors.sh FRAY_CLI DEMO_LIBRARY_DIR
set -uo pipefail
cli=$1 lib=$2
. "$(dirname "$0")/../cli_lib.sh"
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
motion="$lib/walking.bvh"
[[ -f $motion ]] || { echo "FAIL: $motion missing (the build writes the demo library)"; exit 1; }

expect_error() {
  local pattern=$1 rig=$2
  local rc=0
  rm -rf "$tmp/x"
  "$cli" render "$motion" --rig "$rig" --frames 0 --size 64x48 --out "$tmp/x" > /dev/null 2> "$tmp/err.log" || rc=$?
  if (( rc == 0 || rc >= 128 )); then bad "exit code $rc for --rig $rig"; fi
  grep -qF -- "fray-cli: $rig: $pattern" "$tmp/err.log" || bad "expected '$rig: $pattern' -- got: $(cat "$tmp/err.log")"
  (( $(grep -c "" "$tmp/err.log") == 1 )) || bad "expected one line for --rig $rig -- got: $(cat "$tmp/err.log")"
  [[ -e $tmp/x ]] && bad "--rig $rig: the output folder was created before the rig was checked"
}
# A GLB header that promises 4000 bytes and a JSON chunk, then ends.
printf 'glTF\x02\x00\x00\x00\xa0\x0f\x00\x00\x00\x01\x00\x00JSON{"asset":' > "$tmp/cut.glb"
echo "not a rig" > "$tmp/notes.glb"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/triangle.obj"
expect_error "Assimp cannot read the file: " "$tmp/cut.glb"
expect_error "Assimp cannot read the file: " "$tmp/notes.glb"
expect_error "file not found" "$tmp/missing.glb"
expect_error "no mesh in the file (a rig needs a skinned mesh)" "$motion"
expect_error "no skinned mesh: none of the file's 1 meshes has bones" "$tmp/triangle.obj"

if (( fails > 0 )); then echo "$fails failure(s)"; exit 1; fi
echo "cli_render_rig_errors: all checks passed"
