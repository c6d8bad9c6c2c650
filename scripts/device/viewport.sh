#!/bin/bash
# The viewport at crowd scale on a GPU (issue 27): old and new fray-bench alternated twice.
source "$(dirname "$0")/env.sh"
nvidia-smi -L; nproc
args="--benchmark_filter=Viewport720p/(10000|100000) --benchmark_min_time=1.5 --benchmark_repetitions=3 --benchmark_report_aggregates_only=true"
for round in 1 2; do
  for b in ./old/fray-bench ./fray-bench; do
    echo "== $b round $round"
    timeout 120 $b $args 2>&1 | grep -E "median|Run on|ERROR|error" | tee -a "$OUT/viewport.txt"
  done
done
