#!/usr/bin/env bash
# fray (the Qt editor) under Xvfb: opens the demo scene or project with no
# argument, shows N frames with validation on, and writes a screenshot of the
# window and one of the viewport (the renderer's own readback) that are neither
# blank nor uniform and show the characters (pixels of their team colours);
# plays a composed scene the same way, at the time of its Nth frame, and later
# frames show the characters elsewhere; with a skinned rig; clear errors for a
# broken scene or rig, without a Vulkan driver, without a display, with an
# unreachable X server and on a Qt platform without Vulkan windows.
# Usage: editor_xvfb.sh FRAY IMAGE_CHECK DEMO_LIBRARY_DIR OUT_DIR FRAY_CLI
set -uo pipefail
fray=$1 check=$2 lib=$3 out=$4 cli=$5
rm -rf "$out" && mkdir -p "$out"
export XDG_RUNTIME_DIR=$out XDG_CONFIG_HOME=$out/config && chmod 700 "$out"
source "$(dirname "$0")/xvfb_lib.sh"
start_xvfb 1400x900x24 || exit 1

run_window "fray on the demo project" "$out/demo.log" "$fray" --quit-after 10 --validate \
     --screenshot "$out/window.png" --viewport-screenshot "$out/viewport.png"
# Frame k is shown at k/60 s of scene (or take) time: the 10th at 0.150 s.
grep -q "drew 10 frames, at 0.150 s" "$out/demo.log" || bad "expected 10 frames, the last at 0.150 s: $(cat "$out/demo.log")"
"$check" "$out/window.png" 640 400 || bad "window screenshot check"
"$check" "$out/viewport.png" 320 200 || bad "viewport screenshot check"
# The first character is drawn in the first team colour (the demo's first
# take, or the duel's first fighter when command (1) has written the duel);
# an empty floor has no pixel of that hue.
red=$tint_red blue=$tint_blue
"$check" "$out/viewport.png" --tint $red 400 || bad "demo: no character drawn in the viewport"

# The editor on the demo project waits for the background analysis when asked
# and reports it; --describe-ui lists the docks and menus without a display.
if ! timeout 240 "$fray" --quit-after 5 --wait-analysis --fresh-layout --screenshot "$out/editor.png" >"$out/analysis.log" 2>&1; then
  bad "fray --wait-analysis failed: $(cat "$out/analysis.log") $(xvfb_log)"
fi
grep -q "analysed 6 motions, graph [0-9]* nodes" "$out/analysis.log" || bad "no analysis reported: $(cat "$out/analysis.log")"
"$check" "$out/editor.png" 640 400 || bad "editor screenshot check"
"$fray" --describe-ui >"$out/ui.json" 2>"$out/ui.log" || bad "--describe-ui failed: $(cat "$out/ui.log")"
for name in LibraryDock TimelineDock InspectorDock GraphDock CombosDock actionOpen actionQuit plan_preset plan_weight plan_actions compose_crowd; do
  grep -q "\"$name\"" "$out/ui.json" || bad "--describe-ui does not list $name"
done

# A motion file given on the command line.
run_window "fray walking.bvh" "$out/motion.log" "$fray" "$lib/walking.bvh" --quit-after 3

# A composed scene: one-vs-one from the demo project's attack-fall patches.
compose_fight "$cli" "$lib" "$out"
run_window "fray on a scene" "$out/scene.log" "$fray" "$out/fight.frayscene" --quit-after 12 --validate \
     --screenshot "$out/scene-window.png" --viewport-screenshot "$out/scene.png"
grep -q "drew 12 frames, at 0.183 s" "$out/scene.log" || bad "scene: expected 12 frames, the last at 0.183 s: $(cat "$out/scene.log")"
"$check" "$out/scene.png" 320 200 || bad "scene viewport screenshot check"
# Both fighters are drawn in their team colours (side 0 red, side 1 blue;
# the composed fight has no paths or checkpoints in those colours).
"$check" "$out/scene.png" --tint $red 400 || bad "scene: the red fighter is not drawn"
"$check" "$out/scene.png" --tint $blue 400 || bad "scene: the blue fighter is not drawn"
# Playback moves: 36 frames later (0.6 s of fighting) both fighters' pixels
# changed in many places.
run_window "fray on a scene, 48 frames" "$out/later.log" "$fray" "$out/fight.frayscene" --quit-after 48 \
     --viewport-screenshot "$out/scene-later.png"
grep -q "drew 48 frames, at 0.783 s" "$out/later.log" || bad "scene: expected 48 frames, the last at 0.783 s: $(cat "$out/later.log")"
"$check" "$out/scene.png" --differs "$out/scene-later.png" 150 $red || bad "scene: the red fighter did not move"
"$check" "$out/scene.png" --differs "$out/scene-later.png" 150 $blue || bad "scene: the blue fighter did not move"
# The same scene drawn with a skinned rig (the scene exported as GLB); a
# truncated rig is one clear line and exit code 1, before any window.
"$cli" export "$out/fight.frayscene" --format glb --out "$out/rig" -q >"$out/export.log" 2>&1 || bad "export: $(cat "$out/export.log")"
run_window "fray with a rig" "$out/rig.log" "$fray" "$out/fight.frayscene" --rig "$out/rig/fight.glb" --quit-after 6 --validate \
     --viewport-screenshot "$out/rig.png"
"$check" "$out/rig.png" 320 200 || bad "rig viewport screenshot check"
head -c 1000 "$out/rig/fight.glb" > "$out/cut.glb"
rc=0
"$fray" "$lib/walking.bvh" --rig "$out/cut.glb" --quit-after 1 >"$out/badrig.log" 2>&1 || rc=$?
(( rc == 1 )) || bad "broken rig: exit code $rc"
grep -q "^fray: $out/cut.glb: Assimp cannot read the file" "$out/badrig.log" || bad "broken rig message: $(cat "$out/badrig.log")"
# A broken scene file: a clear message naming it, exit code 1, no crash.
expect_broken_scene "$out" "$fray" --quit-after 1
# No Vulkan driver: one line naming mesa-vulkan-drivers, exit code 1, no
# crash (and, with --quit-after, no message box waiting for a click).
expect_no_vulkan_driver "$out" fray "$fray" "$lib/walking.bvh" --quit-after 1

# expect_error PATTERN -- ENV... : exit code 1 and the message, no crash.
expect_error() {
  local pattern=$1; shift
  local rc=0
  env "$@" "$fray" "$lib/walking.bvh" --quit-after 1 >"$out/err.log" 2>&1 || rc=$?
  (( rc == 1 )) || bad "exit code $rc (expected 1) with $*: $(cat "$out/err.log")"
  grep -q -- "$pattern" "$out/err.log" || bad "expected '$pattern' with $*: $(cat "$out/err.log")"
}
expect_error "DISPLAY" -u DISPLAY -u WAYLAND_DISPLAY
expect_error "xvfb-run" -u DISPLAY -u WAYLAND_DISPLAY
# A display number with no server behind it.
dead=97
while [[ -e /tmp/.X11-unix/X$dead || -e /tmp/.X$dead-lock ]]; do dead=$((dead + 1)); done
expect_error "cannot connect to the X server at DISPLAY=:$dead" -u WAYLAND_DISPLAY DISPLAY=:$dead
expect_error "has no Vulkan window surface" QT_QPA_PLATFORM=offscreen

finish_checks editor_xvfb
