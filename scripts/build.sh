#!/usr/bin/env bash
# Installs missing Debian packages, then configures and builds Fray (preset
# "ci": warnings are errors). Shared by the README commands and CI.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
preset=${FRAY_PRESET:-ci}
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j "$(nproc)"
