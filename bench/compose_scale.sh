#!/bin/sh
# Composition at scale (issue 27): the 10,000-character scenes composed by two
# fray-cli binaries, interleaved, ROUNDS times each; prints the composition
# time fray-cli reports, the process's wall, user and system CPU time and peak
# memory. The machine is shared, so read CPU time beside wall time.
#   bench/compose_scale.sh OLD/fray-cli NEW/fray-cli DEMO/demo.frayproj [ROUNDS] [SPEC...]
# DEMO is a demo project with its patch library generated
# (fray-cli demo-library DEMO; fray-cli patches generate DEMO/demo.frayproj).
set -eu
old=$1 new=$2 project=$3 rounds=${4:-2}
shift 3
[ $# -gt 0 ] && shift
here=$(cd "$(dirname "$0")/.." && pwd)
specs=${*:-"$here/bench/rat_crowd_10k.json $here/resources/demo/one_vs_many_crowd.json $here/resources/demo/domino_crowd.json"}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for spec in $specs; do
    for r in $(seq 1 "$rounds"); do
        for which in old new; do
            eval bin=\$$which
            if /usr/bin/time -f '%e %U %S %M' -o "$out/time" "$bin" compose "$project" --spec "$spec" \
                   --out "$out/scene.frayscene" --quiet > "$out/stdout" 2> "$out/stderr"; then
                composed=$(sed -n 's/.*; \([0-9.]*\) s$/\1/p' "$out/stdout" | tail -1)
                set -- $(cat "$out/time")
                printf '%s  %-4s round %s: composed in %s s; process %s s wall, %s s user, %s s sys, %s MB peak\n' \
                    "$(basename "$spec")" "$which" "$r" "$composed" "$1" "$2" "$3" "$(($4 / 1024))"
            else
                printf '%s  %-4s round %s: failed: %s\n' "$(basename "$spec")" "$which" "$r" "$(tail -1 "$out/stderr")"
            fi
        done
    done
done
