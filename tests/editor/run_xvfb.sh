#!/usr/bin/env bash
# Runs a command under a private Xvfb (tests/render/xvfb_lib.sh: the server
# picks its own display, so parallel runs never race for one).
# Usage: run_xvfb.sh COMMAND [ARGS...]
source "$(dirname "$0")/../render/xvfb_lib.sh"
start_xvfb 1600x1000x24 || exit 1
"$@"
code=$?
[[ $code -eq 0 ]] || xvfb_log
exit $code
