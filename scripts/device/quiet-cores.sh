#!/bin/bash
# Quiet 2-core numbers (issues 25, 27): the CPU targets are "on the 2-core machine"; these
# benchmarks run pinned to two cores of an otherwise idle machine, old and new alternated.
source "$(dirname "$0")/env.sh"
lscpu | grep -E "Model name|^CPU\(s\)"
f=${FILTER:-'CrowdComposeAndPose/100000|PosturePhysics/(200/60|1000/30)/0|DemoDuelPlan'}
for b in ./old/fray-bench ./fray-bench; do
  echo "== $b"
  timeout 260 taskset -c 0,1 $b --benchmark_filter="$f" 2>&1 | grep -E "^BM_|ERROR|error" | tee -a "$OUT/quiet2.txt"
done
