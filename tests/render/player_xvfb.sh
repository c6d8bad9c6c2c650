#!/usr/bin/env bash
# fray-play under Xvfb: a fixed number of frames with validation on, a
# screenshot of the window as shown that is neither blank nor uniform, for
# takes, for a composed scene and for the scene with a skinned rig, and clear
# errors without a display, without a Vulkan driver or for a broken scene or
# rig file.
# Usage: player_xvfb.sh FRAY_PLAY IMAGE_CHECK DEMO_LIBRARY_DIR OUT_DIR FRAY_CLI
set -uo pipefail
play=$1 check=$2 lib=$3 out=$4 cli=$5
rm -rf "$out" && mkdir -p "$out"
source "$(dirname "$0")/xvfb_lib.sh"
start_xvfb 1024x768x24 || exit 1

# Two takes side by side, 12 frames, the window captured at the end.
run_window "fray-play" "$out/play.log" "$play" "$lib/walking.bvh" "$lib/shadowbox_energetic.bvh" --frames 12 \
     --size 640x360 --validate --screenshot "$out/play.png"
grep -q "drew 12 frames" "$out/play.log" || bad "expected 12 frames: $(cat "$out/play.log")"
"$check" "$out/play.png" 640 360 || bad "screenshot check"

# The demo project when started with no argument.
run_window "fray-play with no argument" "$out/demo.log" "$play" --frames 2 --size 320x200

# No display: a clear message naming DISPLAY and Xvfb, exit code 1, no crash.
rc=0
env -u DISPLAY -u WAYLAND_DISPLAY "$play" "$lib/walking.bvh" --frames 1 >"$out/nodisplay.log" 2>&1 || rc=$?
(( rc == 1 )) || bad "no display: exit code $rc"
grep -q "DISPLAY" "$out/nodisplay.log" && grep -q "xvfb-run" "$out/nodisplay.log" || bad "no display message: $(cat "$out/nodisplay.log")"

# A composed scene: one-vs-one from the demo project's attack-fall patches,
# played for 12 frames with validation on; the shot is neither blank nor uniform.
compose_fight "$cli" "$lib" "$out"
run_window "fray-play on a scene" "$out/scene.log" "$play" "$out/fight.frayscene" --frames 12 --size 640x360 --validate --screenshot "$out/scene.png"
grep -q "drew 12 frames" "$out/scene.log" || bad "scene: expected 12 frames: $(cat "$out/scene.log")"
"$check" "$out/scene.png" 640 360 || bad "scene screenshot check"
# Both fighters are drawn beside the panel, in their team colours (the
# panel's own swatches are 144 pixels each).
"$check" "$out/scene.png" --tint $tint_red 400 || bad "scene: the red fighter is not drawn beside the panel"
"$check" "$out/scene.png" --tint $tint_blue 400 || bad "scene: the blue fighter is not drawn beside the panel"
# The same scene with a skinned rig (the scene exported as GLB) instead of
# capsules; a broken rig file is one clear line and exit code 1, before any window.
"$cli" export "$out/fight.frayscene" --format glb --out "$out/rig" -q >"$out/export.log" 2>&1 || bad "export: $(cat "$out/export.log")"
run_window "fray-play with a rig" "$out/rig.log" "$play" "$out/fight.frayscene" --rig "$out/rig/fight.glb" --frames 6 --size 640x360 --validate \
     --screenshot "$out/rig.png"
grep -q "drew 6 frames" "$out/rig.log" || bad "rig: expected 6 frames: $(cat "$out/rig.log")"
"$check" "$out/rig.png" 640 360 || bad "rig screenshot check"
head -c 1000 "$out/rig/fight.glb" > "$out/cut.glb"
rc=0
"$play" "$lib/walking.bvh" --rig "$out/cut.glb" --frames 1 >"$out/badrig.log" 2>&1 || rc=$?
(( rc == 1 )) || bad "broken rig: exit code $rc"
grep -q "^fray-play: $out/cut.glb: Assimp cannot read the file" "$out/badrig.log" || bad "broken rig message: $(cat "$out/badrig.log")"
(( $(grep -c "" "$out/badrig.log") == 1 )) || bad "broken rig: expected one line: $(cat "$out/badrig.log")"

# A broken scene file: a clear message, no crash.
expect_broken_scene "$out" "$play" --frames 1

# No Vulkan driver (the loader finds no ICD): one line naming the package to
# install, exit code 1, no crash.
expect_no_vulkan_driver "$out" fray-play "$play" "$lib/walking.bvh" --frames 1

finish_checks player_xvfb
