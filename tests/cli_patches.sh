#!/usr/bin/env bash
# Interaction Patches from the command line on a small demo project: generate
# a patch library from PatternLists stored in the project, list it, compose a
# one-vs-many scene (same seed, same bytes), read its metrics; and bad input:
# an unknown annotation in a PatternList, a pattern no action can satisfy, an
# unknown pattern name, a corrupt or stale patch library, a bad compose spec,
# a file that is not ours. Each is a one-line error that leaves files untouched.
set -eu
cli=$1
. "$(dirname "$0")/cli_lib.sh"

"$cli" demo-library "$tmp/lib" --minutes 3 > /dev/null 2>&1
p=$tmp/lib/demo.frayproj
# PatternLists live in the project file.
python3 - "$p" <<'PY'
import json, sys
path = sys.argv[1]
project = json.load(open(path))
project["pattern_lists"] = {"patterns": [
    {"name": "punch-fall", "entries": [{"character": 1, "annotation": "attack"}, {"character": 2, "annotation": "fall"}],
     "weights": {"contact": 1, "distance": 1, "timing": 1}, "threshold": 0.5},
    {"name": "jab-jab-fall", "entries": [{"character": 1, "annotation": "attack"}, {"character": 1, "annotation": "attack"},
                                          {"character": 2, "annotation": "fall"}]}],
  "initial_conditions": {"attack": {"distance": [0.6, 1.2]}}}
json.dump(project, open(path, "w"), indent=2)
PY
"$cli" patches generate "$p" 2> "$tmp/progress.txt" > "$tmp/gen.txt"
check "progress on stderr" "grep -q 'patches 100%' '$tmp/progress.txt'"
check "per-pattern stats" "grep -q '^punch-fall: .* initial conditions' '$tmp/gen.txt' && grep -q '^jab-jab-fall:' '$tmp/gen.txt'"
check "library beside the project" "[ -s '$p.patches' ] && grep -q 'temporal and .* spatial connections' '$tmp/gen.txt'"
"$cli" patches list "$p" --json -q > "$tmp/list.json"
check "list" "python3 -c 'import json,sys; l=json.load(open(sys.argv[1])); assert len(l) > 5 and all(x[\"score\"] >= 0.5 for x in l)' '$tmp/list.json'"

cat > "$tmp/ovm.json" <<'JSON'
{"kind": "one-vs-many", "duration": 120, "seed": 5, "enemies": 4,
 "commands": [{"time": 0, "action": "punch"}]}
JSON
"$cli" compose "$p" --spec "$tmp/ovm.json" --out "$tmp/ovm.frayscene" 2> /dev/null > "$tmp/compose.txt"
check "composed" "grep -q 'one-vs-many, 5 characters' '$tmp/compose.txt'"
"$cli" compose "$p" --spec "$tmp/ovm.json" --out "$tmp/again.frayscene" -q > /dev/null
check "same seed, same bytes" "cmp -s '$tmp/ovm.frayscene' '$tmp/again.frayscene'"
"$cli" metrics "$tmp/ovm.frayscene" --json -q > "$tmp/metrics.json"
check "no unintended penetration" "python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); assert m[\"penetration_frames\"] == 0, m[\"penetrations\"]; assert m[\"hits\"] >= 4' '$tmp/metrics.json'"

# Bad input.
cp "$p" "$tmp/before.frayproj"
sed 's/"annotation": "fall"/"annotation": "fal"/' "$p" > "$tmp/lib/badann.frayproj"
expect_fail "unknown annotation" "badann.frayproj: /pattern_lists/patterns/0/entries/1/annotation: unknown annotation 'fal'" \
  "$cli" patches generate "$tmp/lib/badann.frayproj" -q
sed 's/"annotation": "fall"/"annotation": "tackle"/' "$p" > "$tmp/lib/nosuch.frayproj"
expect_fail "pattern no action satisfies" "pattern 'punch-fall', entry 2 (character 2, tackle): no action in the project has this annotation" \
  "$cli" patches generate "$tmp/lib/nosuch.frayproj" -q --out "$tmp/nosuch.patches"
expect_fail "unknown pattern" "no PatternList named 'kick-fall'" "$cli" patches generate "$p" --pattern kick-fall -q
echo "my notes" > "$tmp/notes.txt"
expect_fail "never overwrite other files" "refusing to overwrite" "$cli" patches generate "$p" -q --out "$tmp/notes.txt"
check "notes untouched" "[ \"\$(cat '$tmp/notes.txt')\" = 'my notes' ]"
head -c 300 "$p.patches" > "$tmp/cut.patches"
expect_fail "truncated library" "cut.patches: the patch library is truncated or corrupt" \
  "$cli" compose "$p" --spec "$tmp/ovm.json" --patches "$tmp/cut.patches" --out "$tmp/x.frayscene" -q
expect_fail "no library" "no patch library (make it with: fray-cli patches generate" \
  "$cli" compose "$p" --spec "$tmp/ovm.json" --patches "$tmp/missing.patches" --out "$tmp/x.frayscene" -q
echo '{"kind": "one-vs-many", "enemies": -2}' > "$tmp/bad.json"
expect_fail "bad compose spec" "bad.json: /enemies: must be between 1 and 1000" \
  "$cli" compose "$p" --spec "$tmp/bad.json" --out "$tmp/x.frayscene" -q
check "no scene from bad input" "[ ! -e '$tmp/x.frayscene' ]"
check "project untouched by failures" "cmp -s '$p' '$tmp/before.frayproj'"
# A library made before the actions were re-cut is refused.
python3 - "$p" "$tmp/lib/recut.frayproj" <<'PY'
import json, sys
project = json.load(open(sys.argv[1]))
project["motions"][0]["cuts"][0] += 5
json.dump(project, open(sys.argv[2], "w"), indent=2)
PY
cp "$p.patches" "$tmp/lib/recut.frayproj.patches"
expect_fail "stale library" "made from other actions than the project has now" \
  "$cli" compose "$tmp/lib/recut.frayproj" --spec "$tmp/ovm.json" --out "$tmp/x.frayscene" -q
# Domino: people fall inside a painted floor bitmap (PNG), bystanders outside stay up.
python3 - "$p" "$tmp" <<'PY'
import json, struct, sys, zlib
project, tmp = sys.argv[1], sys.argv[2]
def png(path, w, h, colour):
    raw = b''.join(b'\x00' + b''.join(colour(x, y) for x in range(w)) for y in range(h))
    def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 6, 0, 0, 0)) +
                           chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))
black, white, grey = b'\x00\x00\x00\xff', b'\xff\xff\xff\xff', b'\x80\x80\x80\xff'
png(tmp + '/disc.png', 160, 160, lambda x, y: black if (x - 80) ** 2 + (y - 80) ** 2 < 40 ** 2 else white)
png(tmp + '/grey.png', 20, 20, lambda x, y: grey if (x, y) == (3, 4) else white)
open(tmp + '/notpng.png', 'w').write('not an image')
# The project's PatternLists gain the domino pattern.
j = json.load(open(project))
j["pattern_lists"]["patterns"].append({"name": "domino", "entries": [{"character": 1, "annotation": "fall"},
                                       {"character": 2, "annotation": "fall"}], "weights": {"contact": 1, "distance": 0, "timing": 0},
                                       "keep_per_path": 0})
json.dump(j, open(project, "w"), indent=2)
for name, bitmap, start in (("domino", "disc.png", [0, 0]), ("grey", "grey.png", [0, 0]), ("notpng", "notpng.png", [0, 0]),
                            ("outside", "disc.png", [7.5, 7.5]), ("missing", "nothere.png", [0, 0])):
    json.dump({"kind": "domino", "seed": 4, "floor": {"bitmap": bitmap, "metres_per_pixel": 0.1, "origin": [-8, -8]},
               "starts": [{"time": 0.5, "x": start[0], "z": start[1]}], "background": 20}, open(f"{tmp}/{name}.json", "w"))
PY
"$cli" patches generate "$p" --pattern domino --out "$tmp/domino.patches" -q > /dev/null
"$cli" compose "$p" --spec "$tmp/domino.json" --patches "$tmp/domino.patches" --out "$tmp/domino.frayscene" -q > "$tmp/domino.txt"
check "domino composed" "grep -q 'domino, .* chain falls' '$tmp/domino.txt'"
check "domino coverage reported" "grep -q 'the falls cover [0-9]* % of the painted area' '$tmp/domino.txt'"
"$cli" metrics "$tmp/domino.frayscene" --json -q > "$tmp/domino_metrics.json"
check "domino: falls, no penetration" "python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); assert m[\"penetration_frames\"] == 0 and m[\"hits\"] >= 3, m' '$tmp/domino_metrics.json'"
# The scene keeps the painted area for the viewers (tests/render/cli_render_scene.sh
# checks that fray-cli render draws it).
check "domino: the scene keeps the painted area" "python3 -c 'import json,sys; f=json.load(open(sys.argv[1]))[\"floor\"]; assert f[\"width\"] == 160 and f[\"height\"] == 160 and len(f[\"rows\"]) == 160, f.keys()' '$tmp/domino.frayscene'"
expect_fail "non-binary bitmap" "grey.png: not a two-colour image: pixel (3, 4) is #808080" \
  "$cli" compose "$p" --spec "$tmp/grey.json" --patches "$tmp/domino.patches" --out "$tmp/x.frayscene" -q
expect_fail "unreadable bitmap" "notpng.png" \
  "$cli" compose "$p" --spec "$tmp/notpng.json" --patches "$tmp/domino.patches" --out "$tmp/x.frayscene" -q
expect_fail "missing bitmap" "nothere.png" \
  "$cli" compose "$p" --spec "$tmp/missing.json" --patches "$tmp/domino.patches" --out "$tmp/x.frayscene" -q
expect_fail "start off the painted area" "start 0 at (7.5" \
  "$cli" compose "$p" --spec "$tmp/outside.json" --patches "$tmp/domino.patches" --out "$tmp/x.frayscene" -q
check "no scene from a bad bitmap" "[ ! -e '$tmp/x.frayscene' ]"

# American football from the demo actor's football set: the default
# PatternLists the project cannot play (no punches) are skipped, the tackle
# one is generated, and the carrier gets past the tacklers to the goal line.
"$cli" demo-library "$tmp/fb" --set football --minutes 2 > /dev/null 2>&1
"$cli" patches generate "$tmp/fb/demo.frayproj" 2> "$tmp/fb_gen_err.txt" > "$tmp/fb_gen.txt"
check "defaults it cannot play are skipped" "grep -q \"skipping the default pattern 'attack-fall'\" '$tmp/fb_gen_err.txt'"
check "tackle patches generated" "grep -q '^run-tackle-avoid: .* kept' '$tmp/fb_gen.txt'"
cat > "$tmp/football.json" <<'JSON'
{"kind": "football", "seed": 1, "tacklers": 4, "goal": 35, "directions": [{"time": 0, "heading_deg": 0}, {"time": 5, "heading_deg": 20}]}
JSON
"$cli" compose "$tmp/fb/demo.frayproj" --spec "$tmp/football.json" --out "$tmp/football.frayscene" -q > "$tmp/football.txt"
check "football composed (carrier, 4 tacklers and the ball)" "grep -q 'football, 6 characters' '$tmp/football.txt'"
check "carrier past the tacklers to the goal line" "grep -q 'got past 4 tacklers and crossed the goal line' '$tmp/football.txt'"
"$cli" metrics "$tmp/football.frayscene" --json -q > "$tmp/football_metrics.json"
check "football: nobody tackled, no penetration" "python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); assert m[\"penetration_frames\"] == 0 and m[\"hits\"] == 0 and m[\"attacks\"] == 4, m' '$tmp/football_metrics.json'"
echo '{"kind": "football", "directions": [{"time": 0, "heading_deg": 120}]}' > "$tmp/backwards.json"
expect_fail "running away from the goal" "backwards.json: /directions/0/heading_deg: must be within 80 degrees" \
  "$cli" compose "$tmp/fb/demo.frayproj" --spec "$tmp/backwards.json" --out "$tmp/x.frayscene" -q
expect_fail "a football spec on a fighting library" "no tackle patch" \
  "$cli" compose "$p" --spec "$tmp/football.json" --out "$tmp/x.frayscene" -q

# The rat: a one-joint creature through a crowd; no patch library needed
# (the patch file is moved away); everyone near its trajectory gets out of the
# way; the rat is exported with the people.
mv "$p.patches" "$tmp/aside.patches"
sed 's/"crowd": [0-9]*/"crowd": 40/' "$(dirname "$0")/../resources/demo/rat.json" > "$tmp/rat.json"
"$cli" compose "$p" --spec "$tmp/rat.json" --out "$tmp/rat.frayscene" -q > "$tmp/rat.txt"
check "rat composed without a patch library" "grep -q 'rat, 41 characters' '$tmp/rat.txt'"
check "rat: nobody run over" "grep -q ', 0 could not even do that' '$tmp/rat.txt'"
"$cli" metrics "$tmp/rat.frayscene" --json -q > "$tmp/rat_metrics.json"
check "rat: no penetration" "python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); assert m[\"penetration_frames\"] == 0, m' '$tmp/rat_metrics.json'"
"$cli" export "$tmp/rat.frayscene" --format bvh --out "$tmp/rat_bvh" -q > /dev/null
check "rat: a one-joint BVH beside the people" "grep -q '^ROOT rat' '$tmp/rat_bvh/rat_rat.bvh' && [ \$(grep -c JOINT '$tmp/rat_bvh/rat_rat.bvh') -eq 0 ]"
echo '{"kind": "rat", "rat": {"path": [[1, 1]]}}' > "$tmp/no_path.json"
expect_fail "an empty rat trajectory" "no_path.json: /rat/path: the rat's trajectory is empty" \
  "$cli" compose "$p" --spec "$tmp/no_path.json" --out "$tmp/x.frayscene" -q
mv "$tmp/aside.patches" "$p.patches"
echo "PASS"
