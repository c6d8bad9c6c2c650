# Sourced by the window tests. start_xvfb SCREEN starts a private Xvfb on a
# display number the server picks itself (-displayfd), so tests that run in
# parallel never race for the same display the way `xvfb-run -a` can; it
# exports DISPLAY and stops the server when the calling script exits.
start_xvfb() {
  local screen=${1:-1280x1024x24}
  local dir; dir=$(mktemp -d)
  Xvfb -displayfd 3 -screen 0 "$screen" -nolisten tcp 3>"$dir/display" 2>"$dir/xvfb.log" &
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
