#!/usr/bin/env bash
# The editor's UI event loop while it analyses a large project: the demo
# takes resampled to 120 fps (about 8 minutes, ~57,000 frames), contact
# labels scaled to the new rate (so the SVM grid search runs), opened in the
# window test with its stall probe (the longest gap between two 5 ms timer
# ticks of the UI thread while loading, training contacts, segmentation
# profiles and the motion graph run in the worker thread).
# Usage: scripts/editor-responsiveness.sh [BUILD_DIR]   (prints the probe's line)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cli=$build/bin/fray-cli
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
takes=()
for f in "$build"/demo-library/*.bvh; do
  "$cli" convert "$f" "$tmp/$(basename "$f")" --fps 120 >/dev/null
  takes+=("$tmp/$(basename "$f")")
done
"$cli" project new "$tmp/p120.frayproj" --import "${takes[@]}" >/dev/null
# Labels at 120 fps: every frame number doubled.
awk -F, 'NR==1 {print; next} {printf "%s,%d,%d,%s,%s\n", $1, $2*2, $3*2+1, $4, $5}' \
  "$build/demo-library/contact_labels.csv" >"$tmp/labels.csv"
"$cli" contacts "$tmp/p120.frayproj" --train "$tmp/labels.csv" >/dev/null 2>&1
"$cli" segment "$tmp/p120.frayproj" >/dev/null 2>&1
rm -f "$tmp"/p120.frayproj.cache   # the editor trains and analyses from scratch
FRAY_PROBE_PROJECT=$tmp/p120.frayproj QT_QPA_PLATFORM=offscreen XDG_CONFIG_HOME=$tmp/config \
  "$build/bin/fray_editor_window_tests" --gtest_filter='EditorWindow.AnalysisFillsEveryPanel' 2>&1 | grep -E "editor:|OK|FAILED|Failure|Which" | head -20
