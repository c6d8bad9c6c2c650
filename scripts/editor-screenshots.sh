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
trap 'rm -rf "$tmp"' EXIT
export XDG_CONFIG_HOME=$tmp/config XDG_RUNTIME_DIR=$tmp
chmod 700 "$tmp"
xvfb-run -a -s "-screen 0 1600x1000x24" "$build/bin/fray" --quit-after 30 --wait-analysis --fresh-layout \
  --screenshot "$out/editor-window.png" >"$tmp/fray.log" 2>&1 || { cat "$tmp/fray.log"; exit 1; }
QT_QPA_PLATFORM=offscreen "$build/bin/fray_editor_window_tests" --gtest_filter='EditorWindow.AnalysisFillsEveryPanel' \
  >"$tmp/panels.log" 2>&1 || { cat "$tmp/panels.log"; exit 1; }
QT_QPA_PLATFORM=offscreen "$build/bin/fray_editor_tests" >"$tmp/views.log" 2>&1 || { cat "$tmp/views.log"; exit 1; }
QT_QPA_PLATFORM=offscreen "$build/bin/fray_editor_edit_tests" --gtest_filter='EditorEdits.Segmenting*' \
  >"$tmp/edits.log" 2>&1 || { cat "$tmp/edits.log"; exit 1; }
shots=$build/tests/editor/editor-shots
for panel in LibraryDock TimelineDock InspectorDock GraphDock CombosDock HistoryDock; do
  cp "$shots/$panel.png" "$out/editor-${panel%Dock}.png"
done
cp "$shots/inspector-proposals.png" "$out/editor-Inspector-proposals.png"
cp "$shots/timeline-segmented.png" "$out/editor-Timeline-segmented.png"
echo "wrote $out/editor-*.png"
