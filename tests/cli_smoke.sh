#!/usr/bin/env bash
# fray-cli end to end: info (text and JSON), convert with resampling, refusal
# to overwrite the input, clear errors for missing files and bad options.
set -eu
cli=$1; data=$2; shared=$3
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
check() { if ! eval "$2"; then echo "FAIL: $1"; exit 1; fi; }

"$cli" info "$data/bvh_valid/tiny.bvh" > "$tmp/info.txt"
check "info lists joints" "grep -q 'joints      3, 12 channels' '$tmp/info.txt'"
"$cli" info "$data/bvh_valid/tiny.bvh" --json > "$tmp/info.json"
check "json frames" "grep -q '\"frames\": 3' '$tmp/info.json'"

"$cli" convert "$shared/mocap/cmu135_karate/motorcycle.bvh" "$tmp/m60.bvh" --fps 60 2> "$tmp/conv.err"
"$cli" info "$tmp/m60.bvh" --json > "$tmp/m60.json"
check "resampled to 60 fps" "grep -q '\"fps\": 60' '$tmp/m60.json'"
check "291 frames at 120.005 fps become 145 at 60" "grep -q '\"frames\": 145' '$tmp/m60.json'"
check "output in metres" "grep -q '\"units\": \"m\"' '$tmp/m60.json'"

cp "$data/bvh_valid/tiny.bvh" "$tmp/same.bvh"
if "$cli" convert "$tmp/same.bvh" "$tmp/same.bvh" 2> "$tmp/same.err"; then echo "FAIL: overwrote input"; exit 1; fi
check "refuses to overwrite input" "grep -q 'refusing to overwrite' '$tmp/same.err'"
check "input intact" "cmp -s '$data/bvh_valid/tiny.bvh' '$tmp/same.bvh'"

if "$cli" info "$tmp/nope.bvh" 2> "$tmp/nope.err"; then echo "FAIL: missing file accepted"; exit 1; fi
check "missing file named" "grep -q 'nope.bvh: file not found' '$tmp/nope.err'"
if "$cli" info "$data/bvh_valid/tiny.bvh" --units furlongs 2> "$tmp/units.err"; then echo "FAIL: bad --units accepted"; exit 1; fi
check "bad units explained" "grep -q -- '--units: expected' '$tmp/units.err'"
echo "cli_smoke: ok"
