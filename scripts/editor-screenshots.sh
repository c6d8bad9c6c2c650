#!/usr/bin/env bash
# Screenshots for docs/EDITOR.md, made from the code so they stay true:
# the whole editor window on the demo project under Xvfb (the Vulkan viewport
# drawn by lavapipe), and each panel as the offscreen window tests draw it
# after driving it (build/tests/editor/editor-shots).
# Usage: scripts/editor-screenshots.sh [BUILD_DIR]   (after the build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=docs/images
mkdir -p "$out"
tmp=$(mktemp -d)
export XDG_CONFIG_HOME=$tmp/config XDG_RUNTIME_DIR=$tmp
chmod 700 "$tmp"
# One private Xvfb for the windows (the server picks its display: no race
# with other Xvfbs the way xvfb-run -a can have).
source tests/render/xvfb_lib.sh
start_xvfb 1600x1000x24 || exit 1
"$build/bin/fray" --quit-after 30 --wait-analysis --fresh-layout \
  --screenshot "$out/editor-window.png" >"$tmp/fray.log" 2>&1 || { cat "$tmp/fray.log"; exit 1; }
# A duel generated from its demo spec and playing, its action track below the viewport.
"$build/bin/fray" "$build/demo-library/demo.frayproj" \
  --generate resources/demo/duel.json --quit-after 200 --wait-analysis --fresh-layout \
  --screenshot "$out/editor-generate.png" >"$tmp/generate.log" 2>&1 || { cat "$tmp/generate.log"; exit 1; }
QT_QPA_PLATFORM=offscreen "$build/bin/fray_editor_window_tests" --gtest_filter='EditorWindow.AnalysisFillsEveryPanel' \
  >"$tmp/panels.log" 2>&1 || { cat "$tmp/panels.log"; exit 1; }
QT_QPA_PLATFORM=offscreen "$build/bin/fray_editor_tests" >"$tmp/views.log" 2>&1 || { cat "$tmp/views.log"; exit 1; }
QT_QPA_PLATFORM=offscreen "$build/bin/fray_editor_edit_tests" --gtest_filter='EditorEdits.Segmenting*' \
  >"$tmp/edits.log" 2>&1 || { cat "$tmp/edits.log"; exit 1; }
QT_QPA_PLATFORM=offscreen "$build/bin/fray_editor_scene_tests" >"$tmp/scene.log" 2>&1 || { cat "$tmp/scene.log"; exit 1; }
QT_QPA_PLATFORM=offscreen "$build/bin/fray_editor_patches_tests" >"$tmp/patches.log" 2>&1 || { cat "$tmp/patches.log"; exit 1; }
env QT_QPA_PLATFORM=xcb "$build/bin/fray_editor_floor_tests" \
  >"$tmp/floor.log" 2>&1 || { cat "$tmp/floor.log"; exit 1; }
env QT_QPA_PLATFORM=xcb "$build/bin/fray_editor_tools_tests" \
  >"$tmp/tools.log" 2>&1 || { cat "$tmp/tools.log"; exit 1; }
env QT_QPA_PLATFORM=xcb "$build/bin/fray_editor_igraph_tests" \
  >"$tmp/igraph.log" 2>&1 || { cat "$tmp/igraph.log"; exit 1; }
shots=$build/tests/editor/editor-shots
for panel in LibraryDock TimelineDock InspectorDock GraphDock CombosDock HistoryDock; do
  cp "$shots/$panel.png" "$out/editor-${panel%Dock}.png"
done
cp "$shots/inspector-proposals.png" "$out/editor-Inspector-proposals.png"
for panel in SceneDock MetricsDock PatternsDock PatchesDock; do
  cp "$shots/$panel.png" "$out/editor-${panel%Dock}.png"
done
cp "$shots/gantt-duel.png" "$out/editor-Gantt.png"
cp "$shots/setup-box-duel.png" "$out/editor-setup-duel.png"
cp "$shots/setup-box-weights.png" "$out/editor-setup-weights.png"
cp "$shots/gantt-menu.png" "$out/editor-Gantt-menu.png"
cp "$shots/gantt-pinned.png" "$out/editor-Gantt-pinned.png"
cp "$shots/export-dialog.png" "$out/editor-export-dialog.png"
cp "$shots/handmade-dialog.png" "$out/editor-handmade-dialog.png"
cp "$shots/floor-brush.png" "$out/editor-floor-brush.png"
cp "$shots/floor-circle.png" "$out/editor-floor-trajectory.png"
for tool in checkpoints circle-duel rat football commands; do
  cp "$shots/floor-$tool.png" "$out/editor-floor-$tool.png"
done
cp "$shots/timeline-segmented.png" "$out/editor-Timeline-segmented.png"
for shot in igraph-carry-drawn igraph-carry igraph-duel; do
  cp "$shots/$shot-window.png" "$out/editor-$shot.png"
done
rm -rf "$tmp"
echo "wrote $out/editor-*.png"
