#!/usr/bin/env bash
# Editing a generated interaction from the command line (issue 23 item 7,
# docs/TREE_EXPANSION.md "Pins"): on the demo duel, the first punch of red is
# swapped for a kick by pinning it (`fray-cli setup P pin`); after the re-plan
# the kick starts at that time, everything before it is planned as before and
# the scene has no penetration (the duel's `fray-cli metrics` threshold: 0
# samples); unpinning gives back the original scene byte for byte. The same
# seed gives the same bytes with the pin; bad pins are one-line errors naming
# the field, and the project stays untouched. Two halves, so each stays short:
#   cli_pins.sh CLI DEMO_DIR edit    the swap, its checks and the unpin
#   cli_pins.sh CLI DEMO_DIR errors  same seed same bytes with the pin, bad pins
set -eu
cli=$1
demo=$2
mode=$3
. "$(dirname "$0")/cli_lib.sh"

"$cli" demo-library "$tmp/lib" > /dev/null 2>&1
p=$tmp/lib/demo.frayproj
"$cli" setup "$p" import duel --spec "$demo/duel.json" -q > /dev/null
"$cli" simulate "$p" --setup duel --out "$tmp/orig.frayscene" -q > /dev/null
"$cli" actions "$p" --json > "$tmp/actions.json"

# The first punch red throws by its own choice (not its start action).
pick=$(python3 - "$tmp/orig.frayscene" "$tmp/actions.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
notes = {a["name"]: a["annotations"] for a in json.load(open(sys.argv[2]))}
red = scene["characters"][0]
for e in red["track"][1:]:
    if not e["forced"] and "punch" in notes[e["action"]["name"]]:
        print(repr(e["start"]), e["action"]["name"])
        break
PY
)
check "the demo duel has a punch of red" "[ -n '$pick' ]"
read -r T punch <<< "$pick"
echo "swapping red's $punch at $T s for a front_kick"

cp "$p" "$tmp/before.frayproj"
if [[ $mode == errors ]]; then
  "$cli" setup "$p" pin duel --character red --time "$T" --action front_kick -q > /dev/null
  "$cli" simulate "$p" --setup duel --out "$tmp/pinned.frayscene" -q > /dev/null
  "$cli" simulate "$p" --setup duel --out "$tmp/again.frayscene" -q > /dev/null
  check "pinned: same seed, same bytes" "cmp -s '$tmp/pinned.frayscene' '$tmp/again.frayscene'"
  "$cli" setup "$p" unpin duel --character red --time "$T" -q > /dev/null
else
"$cli" setup "$p" pin duel --character red --time "$T" --action front_kick -q > "$tmp/pin.txt"
check "pin reported" "grep -q \"pinned 'front_kick' for 'red'\" '$tmp/pin.txt'"
"$cli" setup "$p" show duel > "$tmp/show.txt"
check "show lists the pin" "grep -q '# pin: red plays front_kick' '$tmp/show.txt'"
"$cli" simulate "$p" --setup duel --out "$tmp/pinned.frayscene" -q > /dev/null
"$cli" metrics "$tmp/pinned.frayscene" -q > "$tmp/metrics.txt"
"$cli" metrics "$tmp/pinned.frayscene" --json -q > "$tmp/metrics.json"
cat "$tmp/metrics.txt"
python3 - "$tmp/orig.frayscene" "$tmp/pinned.frayscene" "$tmp/metrics.json" "$T" <<'PY'
import json, sys
orig, pinned, metrics = (json.load(open(f)) for f in sys.argv[1:4])
T = float(sys.argv[4])
early, late = 1.0 / 30.0, 1.0   # kPinEarly, kPinLate (fray/sim/planner.h)
red = pinned["characters"][0]["track"]
at = [e for e in red if e["start"] >= T - early]
assert at, "red has no action after the pin"
first = at[0]
assert first["action"]["name"] == "front_kick", ("the pinned kick is not there", first)
assert first["start"] <= T + late and not first["forced"], first
assert abs(first["start"] - T) < 1e-9, ("the kick moved", first["start"], T)   # the punch's decision itself
# Everything decided before the pin's time is planned as it was. An action
# still running at the pin's time can end another way (a blow of the old
# scene after the pin cut it short: in the demo duel under the root beam of 16
# blue blocks from 16.82 s and red's cross at 17.29 s, the punch pinned here,
# ends that block at 17.36 s; the kick does not), so its end is compared only
# when it came before the pin.
def decided(e):
    return {k: v for k, v in e.items() if k != "end" or v < T - early}
for a, b in zip(orig["characters"], pinned["characters"]):
    before = [e for e in a["track"] if e["start"] < T - early]
    assert [decided(e) for e in b["track"][:len(before)]] == [decided(e) for e in before], \
        a["name"] + ": the track before the pin changed"
# ... and after it the scene was planned again around the kick.
assert orig["characters"][1]["track"] != pinned["characters"][1]["track"], "blue did not re-plan"
assert pinned["spec"]["pins"] == [{"character": "red", "time": T, "action": "front_kick"}], pinned["spec"].get("pins")
assert metrics["penetration_frames"] == 0, metrics["penetrations"]
assert all(c["penetration_frames"] == 0 for c in metrics["characters"])
print("kick at %.3f s; %d attacks, %d hits, %d penetration samples" % (first["start"], metrics["attacks"], metrics["hits"], metrics["penetration_frames"]))
PY

# Unpinning gives the original scene back, byte for byte, and the project as it was.
"$cli" setup "$p" unpin duel --character 0 --time "$T" -q > /dev/null
"$cli" simulate "$p" --setup duel --out "$tmp/unpinned.frayscene" -q > /dev/null
check "unpin: the original scene" "cmp -s '$tmp/unpinned.frayscene' '$tmp/orig.frayscene'"
check "unpin: the original project" "cmp -s '$p' '$tmp/before.frayproj'"
echo "cli_pins edit: ok"
exit 0
fi

# Bad pins: one line naming the field; the project untouched.
expect_fail "unknown action" "/pins/0/action: no action is named 'kik'" "$cli" setup "$p" pin duel --character red --time 3 --action kik -q
expect_fail "unknown annotation" "/pins/0/action: unknown annotation 'kik'" "$cli" setup "$p" pin duel --character red --time 3 --action @kik -q
expect_fail "reaction" "/pins/0/action: 'knocked_down' is not among the actions 'red' may choose" \
  "$cli" setup "$p" pin duel --character red --time 3 --action knocked_down -q
expect_fail "beyond the scene" "/pins/0/time: 30 s is beyond the scene, which lasts 20 s" \
  "$cli" setup "$p" pin duel --character red --time 30 --action @kick -q
expect_fail "index out of range" "\-\-character: index 2 is out of range" "$cli" setup "$p" pin duel --character 2 --time 3 --action @kick -q
expect_fail "unknown character" "\-\-character: setup 'duel' has no character named 'green'" \
  "$cli" setup "$p" pin duel --character green --time 3 --action @kick -q
expect_fail "no time" "\-\-time: give the time" "$cli" setup "$p" pin duel --character red --action @kick -q
expect_fail "unpin: none there" "\-\-time: 'red' has no pin at" "$cli" setup "$p" unpin duel --character red --time 3 -q
check "project untouched by bad pins" "cmp -s '$p' '$tmp/before.frayproj'"
# A pin the motion graph cannot reach there: blue lies knocked down from its
# first hit (found in the original scene) until long after the pin's window.
down=$(python3 -c "import json,sys; t=[e for e in json.load(open(sys.argv[1]))['characters'][1]['track'] if e['forced'] and e['end']-e['start']>2]; print(repr(t[0]['start']+0.5) if t else '')" "$tmp/orig.frayscene")
check "blue is knocked down in the demo duel" "[ -n '$down' ]"
"$cli" setup "$p" pin duel --character blue --time "$down" --action @kick -q > /dev/null
expect_fail "unreachable" "setup 'duel': /pins/0/action: 'blue' cannot start '@kick' between .*(a reaction to a hit)" \
  "$cli" simulate "$p" --setup duel --out "$tmp/x.frayscene" -q
check "no scene from a pin that cannot be honoured" "[ ! -e '$tmp/x.frayscene' ]"
"$cli" setup "$p" unpin duel --character blue --time "$down" -q > /dev/null
# Compose kinds cannot honour pins: refused, and said so.
"$cli" setup "$p" import one_vs_many --spec "$demo/one_vs_many.json" -q > /dev/null 2>&1
expect_fail "compose kind" "pins are honoured by tree expansion only" \
  "$cli" setup "$p" pin one_vs_many --character 0 --time 1 --action @kick -q
echo "cli_pins errors: ok"
