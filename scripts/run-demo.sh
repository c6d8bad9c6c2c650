#!/usr/bin/env bash
# README command (1): install what is missing, build, and run the main job on
# the embedded demo: generate the synthetic actor's library (takes + ground
# truth) and import every take back through the capture importer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
out=build/demo-library
build/bin/fray-cli demo-library "$out" --seed 1 --report
echo
for take in "$out"/*.bvh; do
  build/bin/fray-cli info "$take" | sed -n '1,3p'
done
echo
echo "Demo library written to $out (BVH takes + ground-truth JSON)."
