#!/usr/bin/env bash
# fray-cli annotate and cuts on a copy of the demo project: every edit kind
# changes exactly what it says (the whole project is compared with the one
# before plus the expected change), edits run in command-line order, and a
# refused edit, or a later edit that fails, leaves the file untouched (same
# bytes, same inode: not even rewritten) with a one-line error naming the flag.
set -eu
cli=$1
lib=$2  # the demo library the build writes
. "$(dirname "$0")/cli_lib.sh"

for f in "$lib"/*.bvh; do ln -s "$f" "$tmp/"; done
p=$tmp/demo.frayproj
cp "$lib/demo.frayproj" "$p"
m=shadowbox_energetic

# Proposals to confirm and reject (the demo project has none).
python3 - "$p" <<'EOF'
import json, sys
p = json.load(open(sys.argv[1]))
acts = next(m for m in p["motions"] if m["id"] == "shadowbox_energetic")["actions"]
acts[3]["proposed"] = ["punch", "avoid", "kick"]
acts[4]["proposed"] = ["kick", "step"]
acts[5]["proposed"] = ["block"]
json.dump(p, open(sys.argv[1], "w"), indent=2)
EOF

# expect_change NAME PYTHON COMMAND...: COMMAND succeeds, and the project
# afterwards equals the one before with PYTHON applied to it (`b`: the project,
# A(i): action i of $m, M: motions by id).
expect_change() {
  local name=$1 change=$2; shift 2
  cp "$p" "$tmp/before.json"
  if ! "$@" > "$tmp/out.txt" 2> "$tmp/err.txt"; then echo "FAIL: $name: $(cat "$tmp/err.txt")"; exit 1; fi
  if ! python3 - "$tmp/before.json" "$p" "$change" <<'EOF'
import json, math, sys
b = json.load(open(sys.argv[1])); a = json.load(open(sys.argv[2]))
M = {m["id"]: m for m in b["motions"]}
def A(i): return M["shadowbox_energetic"]["actions"][i]
exec(sys.argv[3])
if a != b:
    for mb, ma in zip(b["motions"], a["motions"]):
        for k in mb:
            if mb[k] != ma[k]: print("  differs: motion %s %s" % (mb["id"], k))
    sys.exit(1)
EOF
  then echo "FAIL: $name: the project is not the expected one"; exit 1; fi
}
# refused NAME TEXT COMMAND...: fails with one line naming TEXT; the file is not rewritten.
refused() {
  local name=$1
  cp "$p" "$tmp/keep.json"
  local inode; inode=$(stat -c %i "$p")
  expect_fail "$@"
  check "$name: same bytes" "cmp -s '$p' '$tmp/keep.json'"
  check "$name: not rewritten" "[ \$(stat -c %i '$p') = $inode ]"
}

# ---- annotate, one edit kind at a time
expect_change "name" "A(3)['name'] = 'parry_high'" "$cli" annotate "$p" $m 3 --name parry_high
check "summary names the command" "grep -q 'action 3 (parry_high): Name action' '$tmp/out.txt'"
expect_change "add by action name" "A(3)['annotations'].append('dodge')" "$cli" annotate "$p" $m parry_high --add dodge
expect_change "remove" "A(3)['annotations'].remove('block')" "$cli" annotate "$p" $m 3 --remove block
expect_change "confirm" "A(3)['proposed'].remove('avoid'); A(3)['annotations'].append('avoid')" \
  "$cli" annotate "$p" $m 3 --confirm avoid
expect_change "reject" "A(3)['proposed'].remove('kick')" "$cli" annotate "$p" $m 3 --reject kick
expect_change "confirm all" "A(4)['annotations'] += ['kick', 'step']; A(4)['proposed'] = []" \
  "$cli" annotate "$p" $m 4 --confirm-all
check "one command per proposal" "grep -q 'Confirm kick; Confirm step' '$tmp/out.txt'"
expect_change "reject all" "A(5)['proposed'] = []" "$cli" annotate "$p" $m 5 --reject-all
expect_change "joints" "A(3)['joints'] = ['LeftHand', 'RightHand', 'Spine1']" \
  "$cli" annotate "$p" $m 3 --joints 'LeftHand,RightHand , Spine1'
expect_change "clear joints" "A(3)['joints'] = []" "$cli" annotate "$p" $m 3 --joints ''
expect_change "direction" "A(3)['attack_direction'] = 'from_left'" "$cli" annotate "$p" $m 3 --direction from_left
expect_change "no direction" "A(3)['attack_direction'] = None" "$cli" annotate "$p" $m 3 --no-direction
expect_change "defended" "A(4)['defended_part'] = 'torso'" "$cli" annotate "$p" $m 4 --defended torso
expect_change "no defended" "A(4)['defended_part'] = None" "$cli" annotate "$p" $m 4 --no-defended
expect_change "ranges" "A(3)['initial_conditions'] = {'distance': [0.5, 1.25], 'angle': [math.radians(-30), math.radians(30)],
  'facing': [math.radians(150), math.radians(210)], 'timing': [-0.25, 0.5]}" \
  "$cli" annotate "$p" $m 3 --distance 0.5:1.25 --angle -30:30 --facing 150:210 --timing -0.25:0.5
expect_change "one range" "A(3)['initial_conditions']['distance'] = [0.75, 2]" "$cli" annotate "$p" $m 3 --distance 0.75:2
expect_change "no ranges" "A(3)['initial_conditions'] = None" "$cli" annotate "$p" $m 3 --no-ranges
# In command-line order: removing then re-adding moves the word to the end
# (the other order is refused: it is already there).
expect_change "edits in order" "A(2)['annotations'] = ['turn', 'step']; A(2)['name'] = 'pivot'" \
  "$cli" annotate "$p" $m 2 --remove step --name pivot --add step
check "summary lists every command" "grep -q 'Remove annotation; Name action; Annotate action' '$tmp/out.txt'"
expect_change "no change" "pass" "$cli" annotate "$p" $m 2 --name pivot
check "no change said" "grep -q 'nothing changed' '$tmp/out.txt'"

# ---- annotate, refused: nothing written, the flag and the field named
refused "unknown word" "demo.frayproj: --add: motion \\\"$m\\\", action 3: annotation \\\"kik\\\" is not in the project vocabulary" \
  "$cli" annotate "$p" $m 3 --add kik
refused "later edit fails" "--add: .*\\\"kik\\\" is not in the project vocabulary" \
  "$cli" annotate "$p" $m 3 --name renamed --confirm punch --add kik
refused "not a proposal" "--confirm: motion \\\"$m\\\", action 3: \\\"walk\\\" is not a proposal" \
  "$cli" annotate "$p" $m 3 --confirm walk
refused "not annotated" "--remove: .*not annotated \\\"run\\\"" "$cli" annotate "$p" $m 3 --remove run
refused "already annotated" "--add: .*already annotated \\\"avoid\\\"" "$cli" annotate "$p" $m 3 --add avoid
refused "empty joint" "--joints: .*joint 1 has no name" "$cli" annotate "$p" $m 3 --joints 'LeftHand, ,RightHand'
refused "range order" "--distance: MAX 1 is below MIN 2" "$cli" annotate "$p" $m 3 --name x --distance 2:1
refused "range not finite" "--timing MAX: inf is not a finite number" "$cli" annotate "$p" $m 3 --timing 0:inf
refused "range nan" "--angle MIN: nan is not a finite number" "$cli" annotate "$p" $m 3 --angle nan:1
refused "range syntax" "--facing: expected MIN:MAX, got '90'" "$cli" annotate "$p" $m 3 --facing 90
refused "range number" "--distance MAX: expected a number, got '1m'" "$cli" annotate "$p" $m 3 --distance 0:1m
refused "partial ranges" "--facing: motion \\\"$m\\\", action 3 has no initial-condition ranges yet: give --distance, --angle, --facing and --timing together" \
  "$cli" annotate "$p" $m 3 --facing 90:180 --timing 0:1
refused "no such motion" "demo.frayproj: the project has no motion \\\"nope\\\"" "$cli" annotate "$p" nope 0 --name x
refused "no such action" "action 9999: no such action (the motion has" "$cli" annotate "$p" $m 9999 --name x
refused "no such action name" "no action is named \\\"nope\\\"" "$cli" annotate "$p" $m nope --name x
twice=$(python3 -c "
import json, collections, sys
p = json.load(open(sys.argv[1]))
names = [a['name'] for a in next(m for m in p['motions'] if m['id'] == 'shadowbox_energetic')['actions'] if a['name']]
print(next(n for n, c in collections.Counter(names).items() if c > 1))" "$p")
refused "ambiguous action name" "actions are named \\\"$twice\\\" (.*): give the index" "$cli" annotate "$p" $m "$twice" --name x
refused "no edit" "annotate: give at least one edit" "$cli" annotate "$p" $m 3

# ---- cuts
"$cli" cuts "$p" $m list --json > "$tmp/cuts.json"
check "cuts list json" "python3 -c \"
import json, sys
c = json.load(open('$tmp/cuts.json')); p = json.load(open('$p'))
m = next(m for m in p['motions'] if m['id'] == '$m')
assert c['cuts'] == m['cuts'] and c['frame_count'] == m['frame_count']
assert len(c['actions']) == len(m['actions']) and c['actions'][1]['first_frame'] == m['cuts'][0]
assert [a['name'] for a in c['actions']] == [a['name'] for a in m['actions']]\""
check "cuts list text" "'$cli' cuts '$p' $m list | grep -q '^     1      69     113  to_guard'"
# Demo cuts start 69, 114, 146: action 1 spans 69..113.
expect_change "add" "M['$m']['cuts'].insert(1, 100); M['$m']['actions'].insert(2, json.loads(json.dumps(A(1))))" \
  "$cli" cuts "$p" $m add 100
check "add summary" "grep -q 'Add cut (add 100; ' '$tmp/out.txt'"
expect_change "move" "M['$m']['cuts'][1] = 90" "$cli" cuts "$p" $m move 100 90
expect_change "delete" "del M['$m']['cuts'][1]; del M['$m']['actions'][2]" "$cli" cuts "$p" $m delete 90
expect_change "split" "M['$m']['cuts'].insert(0, 30); M['$m']['actions'].insert(1, json.loads(json.dumps(A(0))))" \
  "$cli" cuts "$p" $m split 0 30
expect_change "merge" "l, r = A(1), A(2); l['annotations'] += [w for w in r['annotations'] if w not in l['annotations']]
l['proposed'] += [w for w in r['proposed'] if w not in l['proposed']]; l['joints'] += [j for j in r['joints'] if j not in l['joints']]
del M['$m']['cuts'][1]; del M['$m']['actions'][2]" "$cli" cuts "$p" $m merge 1
expect_change "merge by name" "l, r = A(2), A(3); l['annotations'] += [w for w in r['annotations'] if w not in l['annotations']]
l['proposed'] += [w for w in r['proposed'] if w not in l['proposed']]; l['joints'] += [j for j in r['joints'] if j not in l['joints']]
del M['$m']['cuts'][2]; del M['$m']['actions'][3]" "$cli" cuts "$p" $m merge pivot
refused "cut exists" "demo.frayproj: cuts add: motion \\\"$m\\\": frame 196 is already a cut" "$cli" cuts "$p" $m add 196
refused "not a cut" "cuts delete: motion \\\"$m\\\": frame 197 is not a cut" "$cli" cuts "$p" $m delete 197
refused "move too far" "cuts move: .*cannot move the cut at frame 196 to 9000" "$cli" cuts "$p" $m move 196 9000
refused "split outside" "cuts split: .*action 0: cannot split at frame 0" "$cli" cuts "$p" $m split 0 0
last=$(python3 -c "import json; print(len(next(m for m in json.load(open('$p'))['motions'] if m['id'] == '$m')['actions']) - 1)")
refused "merge last" "cuts merge: .*cannot merge action $last with the next" "$cli" cuts "$p" $m merge $last
refused "frame past the end" "cuts add: .*cannot cut at frame 999999: cuts lie in 1..7182" "$cli" cuts "$p" $m add 999999
refused "frame not a number" "cuts add: FRAME: expected a whole number, got '12.5'" "$cli" cuts "$p" $m add 12.5
refused "arguments" "cuts move: expected move FRAME TO" "$cli" cuts "$p" $m move 146
refused "operation" "cuts: unknown operation 'cut'" "$cli" cuts "$p" $m cut 100
refused "json with an edit" "cuts add: --json goes with list only" "$cli" cuts "$p" $m add 100 --json
refused "cuts no such motion" "the project has no motion \\\"nope\\\"" "$cli" cuts "$p" nope list
expect_fail "missing project" "cannot open the project file" "$cli" cuts "$tmp/none.frayproj" $m list
check "no project created" "[ ! -e '$tmp/none.frayproj' ]"

for verb in annotate cuts; do
  check "$verb --help" "'$cli' $verb --help | grep -q 'ACTION is an index, or a name'"
done
echo "cli_edit: ok"
