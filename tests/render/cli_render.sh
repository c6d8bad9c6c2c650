#!/usr/bin/env bash
# fray-cli render end to end on lavapipe: frames and a contact sheet are
# written (validation on, no messages), and bad input gives one clear line,
# a non-zero exit code and no crash.
# Usage: cli_render.sh FRAY_CLI DEMO_LIBRARY_DIR OUT_DIR
set -uo pipefail
cli=$1 lib=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
motion="$lib/walking.bvh"
[[ -f $motion ]] || { echo "FAIL: $motion missing (the build writes the demo library)"; exit 1; }

# Frames A:B:STEP, B inclusive; names carry the motion frame number.
if ! "$cli" render "$motion" --frames 0:20:10 --size 64x48 --out "$out/frames" --validate --quiet >"$out/ok.log" 2>&1; then
  bad "render of 3 frames failed: $(cat "$out/ok.log")"
fi
for f in 000000 000010 000020; do
  p="$out/frames/frame_$f.png"
  [[ -s $p ]] || bad "missing $p"
  [[ $(head -c 4 "$p" | od -An -c | tr -d ' ') == "211PNG" ]] || bad "$p is not a PNG"
done
[[ $(ls "$out/frames" | wc -l) -eq 3 ]] || bad "expected exactly 3 frames, got: $(ls "$out/frames")"
grep -q "validation" "$out/ok.log" && bad "validation messages: $(cat "$out/ok.log")"

# Contact sheet of the demo project's actions: 2x2 cells of 64x48.
if ! "$cli" render "$lib/demo.frayproj" --contact-sheet --max-cells 4 --size 64x48 --out "$out/sheet" --validate \
     >"$out/sheet.log" 2>&1; then
  bad "contact sheet failed: $(cat "$out/sheet.log")"
fi
[[ -s $out/sheet/sheet_000000.png ]] || bad "missing contact sheet"
grep -q "(128x96)" "$out/sheet.log" || bad "contact sheet size: $(cat "$out/sheet.log")"

# expect_error CODE_MIN PATTERN -- ARGS...: exit code >= CODE_MIN and < 128 (no
# crash), exactly one stderr line, matching PATTERN.
expect_error() {
  local pattern=$1; shift
  local rc=0
  "$@" >"$out/err.out" 2>"$out/err.log" || rc=$?
  if (( rc == 0 || rc >= 128 )); then bad "exit code $rc for: $*"; fi
  grep -q -- "$pattern" "$out/err.log" || bad "expected '$pattern' for: $* -- got: $(cat "$out/err.log")"
  local lines; lines=$(grep -c "^fray-cli:" "$out/err.log")
  (( lines == 1 )) || bad "expected one error line for: $* -- got: $(cat "$out/err.log")"
}
expect_error "nope.bvh" "$cli" render "$out/nope.bvh" --out "$out/x"
expect_error "the last frame (5) is before the first (10)" "$cli" render "$motion" --frames 10:5 --out "$out/x"
expect_error "has [0-9]* frames (0\.\.[0-9]*)" "$cli" render "$motion" --frames 0:999999 --out "$out/x"
expect_error "expected A, A:B or A:B:STEP" "$cli" render "$motion" --frames x:y --out "$out/x"
expect_error "STEP must be" "$cli" render "$motion" --frames 0:10:0 --out "$out/x"
expect_error "expected WIDTHxHEIGHT" "$cli" render "$motion" --size big --out "$out/x"
expect_error "cannot read the file\|No suitable reader" "$cli" render "$lib/demo_library.json" --out "$out/x"
expect_error "cannot create the output folder" "$cli" render "$motion" --frames 0 --out /proc/fray-render-test
# No Vulkan driver: a clear message, not a crash.
VK_ICD_FILENAMES=/nonexistent/icd.json expect_error \
  "no Vulkan device found; install mesa-vulkan-drivers (lavapipe) or a GPU driver" \
  "$cli" render "$motion" --frames 0 --size 64x48 --out "$out/x"

if (( fails > 0 )); then echo "$fails failure(s)"; exit 1; fi
echo "cli_render: all checks passed"
