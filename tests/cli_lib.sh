# Helpers shared by the fray-cli test scripts (sourced): a temporary folder
# removed on exit, `check NAME CONDITION`, and `expect_fail NAME TEXT
# COMMAND...` (the command fails with one stderr line containing TEXT).
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
check() { if ! eval "$2"; then echo "FAIL: $1"; exit 1; fi; }
expect_fail() {
  local name=$1 text=$2; shift 2
  if "$@" 2> "$tmp/err.txt" > /dev/null; then echo "FAIL: $name: succeeded"; exit 1; fi
  check "$name: message" "grep -q -- \"$text\" '$tmp/err.txt'"
  check "$name: one line" "[ \$(wc -l < '$tmp/err.txt') -eq 1 ]"
}
