# Helpers shared by the fray-cli test scripts (sourced): a temporary folder
# removed on exit, `check NAME CONDITION`, `expect_fail NAME TEXT
# COMMAND...` (the command fails with one stderr line containing TEXT), and
# `duel_spec SECONDS DEPTH_RED DEPTH_BLUE` (a two-boxer scene spec on stdout).
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
check() { if ! eval "$2"; then echo "FAIL: $1"; exit 1; fi; }
expect_fail() {
  local name=$1 text=$2; shift 2
  if "$@" 2> "$tmp/err.txt" > /dev/null; then echo "FAIL: $name: succeeded"; exit 1; fi
  check "$name: message" "grep -q -- \"$text\" '$tmp/err.txt'"
  check "$name: one line" "[ \$(wc -l < '$tmp/err.txt') -eq 1 ]"
}
duel_spec() {
  local actions='["@punch", "@kick", "@block", "@avoid", "@step", "@idle", "@transition", "@turn"]'
  cat <<JSON
{"version": 1, "duration": $1, "seed": 3,
 "characters": [
  {"name": "red", "side": 0, "preset": "general-boxer", "depth": $2, "motions": ["shadowbox_energetic"],
   "actions": $actions, "start": {"x": 0, "z": 0, "heading_deg": 90}},
  {"name": "blue", "side": 1, "preset": "infighter", "depth": $3, "motions": ["shadowbox_energetic"],
   "actions": $actions, "start": {"x": 1.2, "z": 0, "heading_deg": -90}}]}
JSON
}
