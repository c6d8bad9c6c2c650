# Sourced by the window tests, which count their failures with bad() and end
# with finish_checks NAME. start_xvfb SCREEN starts a private Xvfb on a
# display number the server picks itself (-displayfd), so tests that run in
# parallel never race for the same display the way `xvfb-run -a` can; it
# exports DISPLAY and stops the server when the calling script exits.
# -noreset: by default the server resets whenever its last client leaves, and
# a window started during that reset could not connect (seen once in CI
# between two runs of fray). xvfb_log prints the server's log for messages.
fails=0
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }

# finish_checks NAME: exit 1 after the count of failures, or say all passed.
finish_checks() {
  if (( fails > 0 )); then echo "$fails failure(s)"; exit 1; fi
  echo "$1: all checks passed"
}

start_xvfb() {
  local screen=${1:-1280x1024x24}
  local dir; dir=$(mktemp -d)
  xvfb_dir=$dir
  Xvfb -displayfd 3 -screen 0 "$screen" -nolisten tcp -noreset 3>"$dir/display" 2>"$dir/xvfb.log" &
  xvfb_pid=$!
  trap 'kill "$xvfb_pid" 2>/dev/null; wait "$xvfb_pid" 2>/dev/null; rm -rf "'"$dir"'"' EXIT
  local i
  for i in $(seq 1 200); do
    # The server writes the number and a newline once it accepts connections.
    if [[ $(wc -l <"$dir/display") -ge 1 ]]; then
      export DISPLAY=":$(head -n 1 "$dir/display")"
      unset WAYLAND_DISPLAY
      return 0
    fi
    if ! kill -0 "$xvfb_pid" 2>/dev/null; then
      echo "Xvfb did not start: $(cat "$dir/xvfb.log")"
      return 1
    fi
    sleep 0.1
  done
  echo "Xvfb did not report a display within 20 s: $(cat "$dir/xvfb.log")"
  return 1
}

xvfb_log() {
  if kill -0 "$xvfb_pid" 2>/dev/null; then echo "(Xvfb on $DISPLAY is running)"; else echo "(Xvfb on $DISPLAY has exited)"; fi
  cat "$xvfb_dir/xvfb.log" 2>/dev/null
}

# run_window WHAT LOG APP ARGS...: APP given ARGS (120 s at most) on the
# Xvfb, its output in LOG; bad() with the output and the server's log when it
# fails, and, when ARGS ask for --validate, when the output has validation
# messages.
run_window() {
  local what=$1 log=$2; shift 2
  if ! timeout 120 "$@" >"$log" 2>&1; then
    bad "$what failed: $(cat "$log") $(xvfb_log)"
  fi
  local arg
  for arg in "$@"; do
    if [[ $arg == --validate ]]; then
      grep -q "validation" "$log" && bad "$what: validation messages: $(cat "$log")"
      break
    fi
  done
}

# The team colours a scene's first characters are drawn in (side 0, side 1:
# render::sideColor), for fray_image_check --tint.
tint_red=0.80,0.30,0.25 tint_blue=0.25,0.45,0.80

# compose_fight CLI LIB OUT: a one-vs-one fight composed from a copy of the
# demo project LIB (attack-fall patches only, for speed), written to
# OUT/fight.frayscene; logs in OUT. Calls bad() on failure.
compose_fight() {
  local cli=$1 lib=$2 out=$3
  cp -r "$lib" "$out/lib"
  "$cli" patches generate "$out/lib/demo.frayproj" --pattern attack-fall --out "$out/lib/demo.frayproj.patches" -q \
    >"$out/gen.log" 2>&1 || bad "patches: $(cat "$out/gen.log")"
  echo '{"kind": "one-vs-one", "duration": 8, "seed": 2}' > "$out/fight.json"
  "$cli" compose "$out/lib/demo.frayproj" --spec "$out/fight.json" --out "$out/fight.frayscene" -q \
    >"$out/compose.log" 2>&1 || bad "compose: $(cat "$out/compose.log")"
}

# expect_play_error CODE WHAT MESSAGE ARGS...: fray-play ($play) given ARGS exits
# with CODE after one line holding MESSAGE (bad input is refused before any
# window opens, so no DISPLAY is needed); the output goes to $out/err.log.
expect_play_error() {
  local code=$1 what=$2 message=$3; shift 3
  local rc=0
  env -u DISPLAY timeout 60 "$play" "$@" --frames 1 >"$out/err.log" 2>&1 || rc=$?
  (( rc == code )) || bad "$what: exit code $rc (expected $code): $(cat "$out/err.log")"
  grep -qF -- "$message" "$out/err.log" || bad "$what: expected '$message': $(cat "$out/err.log")"
  (( $(grep -c "" "$out/err.log") == 1 )) || bad "$what: expected one line: $(cat "$out/err.log")"
}

# expect_broken_scene OUT APP ARGS...: APP given a truncated scene file exits
# with 1 and names the file.
expect_broken_scene() {
  local out=$1; shift
  echo '{"format": "fray-scene"' > "$out/broken.frayscene"
  local rc=0
  timeout 60 "$@" "$out/broken.frayscene" >"$out/broken.log" 2>&1 || rc=$?
  (( rc == 1 )) || bad "broken scene: exit code $rc"
  grep -q "broken.frayscene" "$out/broken.log" || bad "broken scene message: $(cat "$out/broken.log")"
}

# expect_no_vulkan_driver OUT NAME APP ARGS...: APP (which prints errors as
# "NAME: ...") run with the Vulkan loader pointed at a driver manifest that
# does not exist (VK_DRIVER_FILES, and VK_ICD_FILENAMES for older loaders)
# exits with 1 after one line that names mesa-vulkan-drivers; a crash or a
# hang fails.
expect_no_vulkan_driver() {
  local out=$1 name=$2; shift 2
  local rc=0
  VK_DRIVER_FILES=/nonexistent/fray_icd.json VK_ICD_FILENAMES=/nonexistent/fray_icd.json timeout 60 "$@" \
    >"$out/nodriver.log" 2>&1 || rc=$?
  (( rc == 1 )) || bad "no Vulkan driver: exit code $rc (expected 1): $(cat "$out/nodriver.log")"
  grep -q "^$name: no Vulkan device found; install mesa-vulkan-drivers" "$out/nodriver.log" ||
    bad "no Vulkan driver message: $(cat "$out/nodriver.log")"
  (( $(grep -c "" "$out/nodriver.log") == 1 )) || bad "no Vulkan driver: expected one line: $(cat "$out/nodriver.log")"
}
