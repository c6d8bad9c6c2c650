#!/usr/bin/env bash
# README command (1): install what is missing, build, and run the main job on
# the embedded demo. The build generates the synthetic actor's library (takes,
# ground truth, contact labels and the demo project) in build/demo-library.
# The data-preparation pipeline then runs from scratch on those takes: a new
# project, SVM foot contacts trained on the 20 s of labels, automatic
# segmentation with annotation proposals, and the action-level motion graph.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
lib=build/demo-library
run=build/demo-run
cli=build/bin/fray-cli
mkdir -p "$run"
"$cli" project new "$run/auto.frayproj" --force --import "$lib"/*.bvh
"$cli" contacts "$run/auto.frayproj" --train "$lib/contact_labels.csv"
"$cli" segment "$run/auto.frayproj"
"$cli" graph "$run/auto.frayproj"
echo
echo "The authored demo project (ground-truth cuts and annotations):"
"$cli" graph "$lib/demo.frayproj" --quiet
echo
echo "Automatic project: $run/auto.frayproj (list its actions: $cli actions $run/auto.frayproj)"
echo "Demo project:      $lib/demo.frayproj"
