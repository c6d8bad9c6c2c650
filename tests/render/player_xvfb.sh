#!/usr/bin/env bash
# fray-play under Xvfb: a fixed number of frames with validation on, a
# screenshot of the window as shown that is neither blank nor uniform, and
# clear errors without a display or for a scene file.
# Usage: player_xvfb.sh FRAY_PLAY IMAGE_CHECK DEMO_LIBRARY_DIR OUT_DIR
set -uo pipefail
play=$1 check=$2 lib=$3 out=$4
rm -rf "$out" && mkdir -p "$out"
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
source "$(dirname "$0")/xvfb_lib.sh"
start_xvfb 1024x768x24 || exit 1

# Two takes side by side, 12 frames, the window captured at the end.
if ! timeout 120 "$play" "$lib/walking.bvh" "$lib/shadowbox_energetic.bvh" --frames 12 \
     --size 640x360 --validate --screenshot "$out/play.png" >"$out/play.log" 2>&1; then
  bad "fray-play failed: $(cat "$out/play.log")"
fi
grep -q "drew 12 frames" "$out/play.log" || bad "expected 12 frames: $(cat "$out/play.log")"
grep -q "validation" "$out/play.log" && bad "validation messages: $(cat "$out/play.log")"
"$check" "$out/play.png" 640 360 || bad "screenshot check"

# The demo project when started with no argument.
if ! timeout 120 "$play" --frames 2 --size 320x200 >"$out/demo.log" 2>&1; then
  bad "fray-play with no argument failed: $(cat "$out/demo.log")"
fi

# No display: a clear message naming DISPLAY and Xvfb, exit code 1, no crash.
rc=0
env -u DISPLAY -u WAYLAND_DISPLAY "$play" "$lib/walking.bvh" --frames 1 >"$out/nodisplay.log" 2>&1 || rc=$?
(( rc == 1 )) || bad "no display: exit code $rc"
grep -q "DISPLAY" "$out/nodisplay.log" && grep -q "xvfb-run" "$out/nodisplay.log" || bad "no display message: $(cat "$out/nodisplay.log")"

# A scene file is refused for now, with a reason.
touch "$out/duel.frayscene"
rc=0
"$play" "$out/duel.frayscene" --frames 1 >"$out/scene.log" 2>&1 || rc=$?
(( rc != 0 && rc < 128 )) || bad "scene file: exit code $rc"
grep -q "scene files cannot be played yet" "$out/scene.log" || bad "scene message: $(cat "$out/scene.log")"

if (( fails > 0 )); then echo "$fails failure(s)"; exit 1; fi
echo "player_xvfb: all checks passed"
