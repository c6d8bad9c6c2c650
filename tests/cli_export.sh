#!/usr/bin/env bash
# fray-cli export on a small planned duel: glTF (default), GLB, BVH and FBX
# files and their scene summaries; the same scene gives the same bytes; the
# files read back (BVH through our reader and Assimp, FBX and glTF through
# Assimp via `info`, every character); BVH rotation channels continuous; and
# bad input (a name that is not file-safe among them): a missing or corrupt scene, an unknown format, a
# bad --fps, folders that cannot be created or written, a file that is not an
# earlier export. Each is a one-line error naming the file.
set -eu
cli=$1
. "$(dirname "$0")/cli_lib.sh"

"$cli" demo-library "$tmp/lib" --minutes 3 > /dev/null 2>&1
duel_spec 5 2 2 > "$tmp/duel.json"
"$cli" simulate "$tmp/lib/demo.frayproj" --spec "$tmp/duel.json" --out "$tmp/duel.frayscene" -q > /dev/null
s=$tmp/duel.frayscene

"$cli" export --help > "$tmp/help.txt"
check "help names the formats" "grep -q 'glb' '$tmp/help.txt' && grep -q -- '--fps' '$tmp/help.txt'"

# glTF is the default; the folder is created; progress goes to stderr.
"$cli" export "$s" --out "$tmp/a/gltf" 2> "$tmp/progress.txt" > "$tmp/out.txt"
check "progress on stderr" "grep -q 'export: writing 100%' '$tmp/progress.txt'"
check "summary on stdout" "grep -q '151 frames at 30 fps' '$tmp/out.txt' && grep -q 'duel.gltf' '$tmp/out.txt'"
check "gltf written" "grep -q '\"version\": \"2.0\"' '$tmp/a/gltf/duel.gltf'"
check "scene summary written" "grep -q '\"format\": \"fray-export\"' '$tmp/a/gltf/duel.gltf.scene.json'"
check "summary names the actions" "grep -q '\"label\":' '$tmp/a/gltf/duel.gltf.scene.json'"
"$cli" export "$s" --format glb --out "$tmp/a/glb" -q > /dev/null
check "glb magic" "[ \"\$(head -c 4 '$tmp/a/glb/duel.glb')\" = glTF ]"
"$cli" export "$s" --format bvh --out "$tmp/a/bvh" -q > /dev/null
check "one bvh per character" "[ -f '$tmp/a/bvh/duel_red.bvh' ] && [ -f '$tmp/a/bvh/duel_blue.bvh' ]"
"$cli" export "$s" --format fbx --out "$tmp/a/fbx" --fps 24 -q > /dev/null
check "fbx written" "head -c 18 '$tmp/a/fbx/duel.fbx' | grep -q 'Kaydara FBX Binary'"
check "fps recorded" "grep -q '\"fps\": 24' '$tmp/a/fbx/duel.fbx.scene.json'"
check "summary positions in metres" "grep -q '\"units\": \"m\"' '$tmp/a/fbx/duel.fbx.scene.json' && grep -q '\"file_units\": \"cm\"' '$tmp/a/fbx/duel.fbx.scene.json'"

# Read back: BVH through our reader, and the rest through Assimp.
"$cli" info "$tmp/a/bvh/duel_red.bvh" --json > "$tmp/info.json"
check "bvh frames" "grep -q '\"frames\": 151' '$tmp/info.json'"
check "bvh joints" "grep -q '\"joints\": 24' '$tmp/info.json'"
"$cli" info "$tmp/a/glb/duel.glb" --json > "$tmp/info_glb.json"
check "glb read by Assimp" "grep -q '\"frames\": 151' '$tmp/info_glb.json'"
# Every character of a multi-character file, each with its own 24 joints.
check "glb: both characters" "grep -q '\"skeleton_count\": 2' '$tmp/info_glb.json' && [ \$(grep -c '\"joints\": 24' '$tmp/info_glb.json') -eq 3 ]"
"$cli" info "$tmp/a/fbx/duel.fbx" --json > "$tmp/info_fbx.json"
# Both characters, 24 joints each, at the export's 24 fps (121 frames over 5 s), in centimetres.
check "fbx: both characters" "grep -q '\"skeleton_count\": 2' '$tmp/info_fbx.json' && [ \$(grep -c '\"joints\": 24' '$tmp/info_fbx.json') -eq 3 ]"
check "fbx: frame rate" "grep -q '\"fps\": 24.0' '$tmp/info_fbx.json' && grep -q '\"frames\": 121' '$tmp/info_fbx.json'"
check "fbx: units" "grep -q '\"units\": \"cm\"' '$tmp/info_fbx.json'"
"$cli" info "$tmp/a/fbx/duel.fbx" > "$tmp/info_fbx.txt"
check "fbx: text names each skeleton" "grep -q 'skeleton   2 of 2, root blue_Hips' '$tmp/info_fbx.txt'"
# BVH rotation channels continuous: no value moves by more than 180 degrees between frames.
bvh_jumps() { awk -f "$(dirname "$0")/export/bvh_jumps.awk" "$1"; }
check "bvh channels continuous" "[ \$(bvh_jumps '$tmp/a/bvh/duel_red.bvh') -eq 0 ] && [ \$(bvh_jumps '$tmp/a/bvh/duel_blue.bvh') -eq 0 ]"

# Same scene, same bytes (a second process, so no state is shared).
for f in gltf glb bvh fbx; do
  "$cli" export "$s" --format $f --out "$tmp/b/$f" -q $([ $f = fbx ] && echo --fps 24) > /dev/null
  for file in "$tmp/a/$f"/*; do
    check "$f: $(basename "$file") identical" "cmp -s '$file' '$tmp/b/$f/$(basename "$file")'"
  done
done
# Re-exporting over our own files is fine, also in another format.
"$cli" export "$s" --format bvh --out "$tmp/a/gltf" -q > /dev/null
"$cli" export "$s" --out "$tmp/a/gltf" -q > /dev/null

# Errors: one line naming the file and the problem; nothing written.
expect_fail "missing scene" "$tmp/none.frayscene: cannot open the scene file: no such file" \
  "$cli" export "$tmp/none.frayscene" --out "$tmp/c"
printf '{"format": "fray-scene", "version": 1, "project": ' > "$tmp/bad.frayscene"
expect_fail "corrupt scene" "$tmp/bad.frayscene:1:[0-9]*: not valid JSON" "$cli" export "$tmp/bad.frayscene" --out "$tmp/c"
expect_fail "unknown format" "export: unknown format 'obj' (expected gltf, glb, bvh or fbx)" \
  "$cli" export "$s" --format obj --out "$tmp/c"
expect_fail "bad fps" "export: --fps must be between 1 and 1000" "$cli" export "$s" --fps 0 --out "$tmp/c"
check "no folder for bad input" "[ ! -e '$tmp/c' ]"
echo "my notes" > "$tmp/notes.txt"
expect_fail "folder under a file" "$tmp/notes.txt/out: cannot create the output folder" \
  "$cli" export "$s" --out "$tmp/notes.txt/out" -q
expect_fail "unwritable folder" "/proc/self: cannot write in the output folder" "$cli" export "$s" --out /proc/self -q
mkdir -p "$tmp/mine" && cp "$tmp/notes.txt" "$tmp/mine/duel.glb"
expect_fail "never overwrite other files" "$tmp/mine/duel.glb: exists and is not a file of an earlier Fray export; refusing to overwrite it" \
  "$cli" export "$s" --format glb --out "$tmp/mine" -q
check "notes untouched" "cmp -s '$tmp/notes.txt' '$tmp/mine/duel.glb'"
check "no summary written" "[ ! -e '$tmp/mine/duel.glb.scene.json' ]"
# Names: a space is refused with a suggestion; a scene file's stem is made file-safe.
expect_fail "name with a space" "export: the name 'my duel' has the character ' '; use only letters, digits, '_', '-' and '.' (e.g. 'my_duel')" \
  "$cli" export "$s" --name 'my duel' --out "$tmp/d" -q
check "nothing written for a bad name" "[ ! -e '$tmp/d' ]"
cp "$s" "$tmp/my duel.frayscene"
"$cli" export "$tmp/my duel.frayscene" --out "$tmp/e" -q > /dev/null
check "stem made file-safe" "[ -f '$tmp/e/my_duel.gltf' ] && [ -f '$tmp/e/my_duel.gltf.scene.json' ]"
echo "PASS"
