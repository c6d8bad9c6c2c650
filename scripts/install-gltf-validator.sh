#!/usr/bin/env bash
# Installs the Khronos glTF-Validator (npm package gltf-validator, pinned) into
# build-tools/gltf-validator for scripts/validate-gltf.mjs and the export
# tests. Node.js and npm come from Debian 12 (nodejs, npm) when the commands
# are missing; a node that is already installed (e.g. from NodeSource, which
# bundles npm and conflicts with Debian's npm package) is used as it is.
# Idempotent: does nothing when the pinned version is already there.
set -euo pipefail
cd "$(dirname "$0")/.."
version=2.0.0-dev.3.10
prefix=build-tools/gltf-validator

if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  echo "install-gltf-validator: installing the Debian packages nodejs npm"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends nodejs npm
fi

installed=$(node -e "try { console.log(require('./$prefix/node_modules/gltf-validator/package.json').version) } catch { }")
if [[ "$installed" == "$version" ]]; then
  echo "install-gltf-validator: gltf-validator $version present"
  exit 0
fi
echo "install-gltf-validator: npm install gltf-validator@$version into $prefix"
mkdir -p "$prefix"
npm install --prefix "$prefix" --no-audit --no-fund --loglevel=error --save-exact "gltf-validator@$version"
