#!/usr/bin/env bash
# fray-cli render of a planned scene: a short duel simulated on a small demo
# library renders offscreen (frames at 30 per second of scene time), and a
# frame range past the scene's end is a one-line error.
set -eu
cli=$1
. "$(dirname "$0")/../cli_lib.sh"

"$cli" demo-library "$tmp/lib" --minutes 3 > /dev/null 2>&1
cat > "$tmp/duel.json" <<'JSON'
{"duration": 4, "seed": 1, "characters": [
  {"name": "red", "side": 0, "depth": 2, "motions": ["shadowbox_energetic"], "start": {"x": 0, "z": 0, "heading_deg": 90}},
  {"name": "blue", "side": 1, "depth": 2, "motions": ["shadowbox_energetic"], "start": {"x": 1.2, "z": 0, "heading_deg": -90}}]}
JSON
"$cli" simulate "$tmp/lib/demo.frayproj" --spec "$tmp/duel.json" --out "$tmp/duel.frayscene" -q > /dev/null
"$cli" render "$tmp/duel.frayscene" --frames 0:60:30 --size 160x90 --fast --labels --validate --quiet --out "$tmp/frames" > /dev/null
check "scene frames" "[ -f '$tmp/frames/frame_000000.png' ] && [ -f '$tmp/frames/frame_000060.png' ] && [ ! -f '$tmp/frames/frame_000090.png' ]"
expect_fail "scene frame range" "the scene has 121 frames" \
  "$cli" render "$tmp/duel.frayscene" --frames 500 --out "$tmp/frames" --quiet
# A painted floor area kept in the scene file (a domino scene's "floor") is
# laid on the floor: the same frame with it is a different image. A bad one is
# a one-line error naming the field.
python3 - "$tmp/duel.frayscene" "$tmp/floor.frayscene" "$tmp/badfloor.frayscene" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["floor"] = {"width": 8, "height": 8, "origin": [-2, -2], "metres_per_pixel": 0.5, "rows": ["0 8"] * 8}
json.dump(s, open(sys.argv[2], "w"))
s["floor"]["rows"][3] = "2 x"
json.dump(s, open(sys.argv[3], "w"))
PY
"$cli" render "$tmp/floor.frayscene" --frames 0 --size 160x90 --fast --pitch 60 --validate --quiet --out "$tmp/floor_on" > /dev/null
"$cli" render "$tmp/duel.frayscene" --frames 0 --size 160x90 --fast --pitch 60 --validate --quiet --out "$tmp/floor_off" > /dev/null
check "the painted floor is drawn" "! cmp -s '$tmp/floor_on/frame_000000.png' '$tmp/floor_off/frame_000000.png'"
expect_fail "bad floor rows" "badfloor.frayscene: /floor/rows/3: must be run lengths" \
  "$cli" render "$tmp/badfloor.frayscene" --frames 0 --out "$tmp/frames" --quiet
echo "PASS"
