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
echo "PASS"
