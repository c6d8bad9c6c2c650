#!/usr/bin/env bash
# README command (2): setup, build, and the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --preset "${FRAY_PRESET:-ci}" -j "$(nproc)"
