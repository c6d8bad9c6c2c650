#!/usr/bin/env bash
# README command (1): install what is missing, build, and run the main job on
# the embedded demo. The build generates the synthetic actor's library (takes +
# ground truth) in build/demo-library; every take is then imported back through
# the capture importer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
out=build/demo-library
for take in "$out"/*.bvh; do
  build/bin/fray-cli info "$take" | sed -n '1,3p'
done
echo
echo "Demo library in $out (BVH takes + ground-truth JSON)."
echo "Quality figures: build/bin/fray-cli demo-library /tmp/demo --report"
