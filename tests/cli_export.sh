#!/usr/bin/env bash
# fray-cli export on a small planned duel: glTF (default), GLB, BVH and FBX
# files and the scene summary; the same scene gives the same bytes; the files
# read back (BVH through our reader and Assimp, FBX and glTF through Assimp
# via `info`); and bad input: a missing or corrupt scene, an unknown format, a
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
check "scene summary written" "grep -q '\"format\": \"fray-export\"' '$tmp/a/gltf/duel.scene.json'"
check "summary names the actions" "grep -q '\"label\":' '$tmp/a/gltf/duel.scene.json'"
"$cli" export "$s" --format glb --out "$tmp/a/glb" -q > /dev/null
check "glb magic" "[ \"\$(head -c 4 '$tmp/a/glb/duel.glb')\" = glTF ]"
"$cli" export "$s" --format bvh --out "$tmp/a/bvh" -q > /dev/null
check "one bvh per character" "[ -f '$tmp/a/bvh/duel_red.bvh' ] && [ -f '$tmp/a/bvh/duel_blue.bvh' ]"
"$cli" export "$s" --format fbx --out "$tmp/a/fbx" --fps 24 -q > /dev/null
check "fbx written" "head -c 18 '$tmp/a/fbx/duel.fbx' | grep -q 'Kaydara FBX Binary'"
check "fps recorded" "grep -q '\"fps\": 24' '$tmp/a/fbx/duel.scene.json'"

# Read back: BVH through our reader, and the rest through Assimp.
"$cli" info "$tmp/a/bvh/duel_red.bvh" --json > "$tmp/info.json"
check "bvh frames" "grep -q '\"frames\": 151' '$tmp/info.json'"
check "bvh joints" "grep -q '\"joints\": 24' '$tmp/info.json'"
"$cli" info "$tmp/a/glb/duel.glb" --json > "$tmp/info_glb.json"
check "glb read by Assimp" "grep -q '\"frames\": 151' '$tmp/info_glb.json'"
"$cli" info "$tmp/a/fbx/duel.fbx" --json > "$tmp/info_fbx.json"
# Both characters' joints under the common root (RootNode, red, blue + 2 x 24), in centimetres.
check "fbx read by Assimp" "grep -q '\"joints\": 51' '$tmp/info_fbx.json' && grep -q '\"units\": \"cm\"' '$tmp/info_fbx.json'"

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
check "no summary written" "[ ! -e '$tmp/mine/duel.scene.json' ]"
echo "PASS"
