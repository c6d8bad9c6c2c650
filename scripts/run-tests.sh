#!/usr/bin/env bash
# README command (2): setup, build, and the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
# Node.js and the Khronos glTF-Validator for the export tests (the ci preset
# fails, not skips, export_gltf_validator without them).
bash scripts/install-gltf-validator.sh
ctest --preset "${FRAY_PRESET:-ci}" -j "$(nproc)"
