#!/usr/bin/env bash
# Every malformed BVH must make `fray-cli info` exit non-zero within 10 s with
# its specific one-line error, and leave the file untouched.
set -u
cli=$1; dir=$2
fails=0; n=0
while IFS=$'\t' read -r file expected; do
  [[ -z $file || $file == \#* ]] && continue
  n=$((n + 1))
  before=$(sha256sum "$dir/$file" | cut -d' ' -f1)
  err=$(timeout 10 "$cli" info "$dir/$file" 2>&1 >/dev/null); rc=$?
  after=$(sha256sum "$dir/$file" | cut -d' ' -f1)
  lines=$(printf '%s\n' "$err" | wc -l)
  if [[ $rc == 0 || $rc == 124 || $rc -ge 128 ]]; then echo "FAIL $file: exit code $rc"; fails=$((fails + 1));
  elif [[ $err != *"$file:"* || $err != *"$expected"* ]]; then echo "FAIL $file: got '$err', want '$expected'"; fails=$((fails + 1));
  elif [[ $lines != 1 ]]; then echo "FAIL $file: $lines lines on stderr"; fails=$((fails + 1));
  elif [[ $before != "$after" ]]; then echo "FAIL $file: file changed"; fails=$((fails + 1)); fi
done < "$dir/EXPECTED.tsv"
echo "cli_malformed: $n files, $fails failures"
[[ $n -ge 25 && $fails == 0 ]]
