#!/usr/bin/env bash
# README command (1): install what is missing, build, and run the main job on
# the embedded demo. The build generates the synthetic actor's library (takes,
# ground truth, contact labels and the demo project) in build/demo-library.
# The data-preparation pipeline then runs from scratch on those takes: a new
# project, SVM foot contacts trained on the 20 s of labels, automatic
# segmentation with annotation proposals, and the action-level motion graph.
# Then the planner: a duel planned by min-max tree expansion on the authored
# demo project (resources/demo/duel.json), its metrics, a few frames rendered
# offscreen, the duel exported as glTF (docs/EXPORT.md); Interaction Patches
# generated from the demo PatternLists, a one-vs-many fight and a domino crowd
# composed from them; the football set of the demo actor and an American
# football run composed from its tackle patches; a rat running through a
# crowd; and the `fray` window playing
# the duel when a display is available.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
lib=build/demo-library
run=build/demo-run
cli=build/bin/fray-cli
mkdir -p "$run"
"$cli" project new "$run/auto.frayproj" --force --import "$lib"/*.bvh
"$cli" contacts "$run/auto.frayproj" --train "$lib/contact_labels.csv"
"$cli" segment "$run/auto.frayproj"
"$cli" graph "$run/auto.frayproj"
echo
echo "The authored demo project (ground-truth cuts and annotations):"
"$cli" graph "$lib/demo.frayproj" --quiet
echo
echo "A duel planned by tree expansion (resources/demo/duel.json):"
"$cli" simulate "$lib/demo.frayproj" --spec resources/demo/duel.json --out "$run/duel.frayscene" --quiet
"$cli" metrics "$run/duel.frayscene" --quiet
"$cli" render "$run/duel.frayscene" --frames 0:600:60 --size 960x540 --labels --quiet --out "$run/duel-frames"
"$cli" export "$run/duel.frayscene" --out "$run/duel-export" --quiet
echo
echo "A chase on a 6 m stage: two chasers corner a runaway (resources/demo/chase.json):"
"$cli" simulate "$lib/demo.frayproj" --spec resources/demo/chase.json --out "$run/chase.frayscene" --quiet
"$cli" metrics "$run/chase.frayscene" --quiet
"$cli" render "$run/chase.frayscene" --frames 0:end:90 --size 960x540 --labels --quiet --out "$run/chase-frames"
echo
echo "Interaction Patches from the demo PatternLists, and a one-vs-many fight composed from them:"
"$cli" patches generate "$lib/demo.frayproj" --out "$run/demo.patches" --quiet
"$cli" compose "$lib/demo.frayproj" --patches "$run/demo.patches" --spec resources/demo/one_vs_many.json --out "$run/one_vs_many.frayscene" --quiet
"$cli" metrics "$run/one_vs_many.frayscene" --quiet
"$cli" render "$run/one_vs_many.frayscene" --frames 0:end:150 --size 960x540 --labels --quiet --out "$run/one_vs_many-frames"
echo "A crowd falling like dominoes into the painted areas of resources/demo/domino_floor.png:"
"$cli" compose "$lib/demo.frayproj" --patches "$run/demo.patches" --spec resources/demo/domino.json --out "$run/domino.frayscene" --quiet
"$cli" metrics "$run/domino.frayscene" --quiet | grep "^scene:"
"$cli" render "$run/domino.frayscene" --frames 0:end:60 --size 960x540 --pitch 40 --quiet --out "$run/domino-frames"
echo
echo "American football: the demo actor's football takes (runs, cuts, dives), patches of {run, TACKLE, avoid},"
echo "and a carrier running for the goal line past six tacklers the way resources/demo/football.json points:"
"$cli" demo-library "$run/football-library" --set football > /dev/null 2>&1
"$cli" patches generate "$run/football-library/demo.frayproj" --quiet
"$cli" compose "$run/football-library/demo.frayproj" --spec resources/demo/football.json --out "$run/football.frayscene" --quiet
"$cli" metrics "$run/football.frayscene" --quiet | grep "^scene:"
"$cli" render "$run/football.frayscene" --frames 0:end:30 --size 960x540 --labels --yaw 120 --quiet --out "$run/football-frames"
echo
echo "A rat running along resources/demo/rat.json's trajectory through a crowd: people step out of its way"
echo "and bump into their neighbours (the rat is a one-joint character):"
"$cli" compose "$lib/demo.frayproj" --spec resources/demo/rat.json --out "$run/rat.frayscene" --quiet
"$cli" metrics "$run/rat.frayscene" --quiet | grep "^scene:"
"$cli" render "$run/rat.frayscene" --frames 0:end:30 --size 960x540 --camera follow --pitch 35 --quiet --out "$run/rat-frames"
echo
echo "Automatic project: $run/auto.frayproj (list its actions: $cli actions $run/auto.frayproj)"
echo "Demo project:      $lib/demo.frayproj"
echo "Duel scene:        $run/duel.frayscene (frames in $run/duel-frames, glTF in $run/duel-export)"
echo "Chase:             $run/chase.frayscene (frames in $run/chase-frames)"
echo "One vs many:       $run/one_vs_many.frayscene (frames in $run/one_vs_many-frames)"
echo "Domino:            $run/domino.frayscene (frames in $run/domino-frames)"
echo "Football:          $run/football.frayscene (frames in $run/football-frames)"
echo "Rat:               $run/rat.frayscene (frames in $run/rat-frames)"
if [[ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" && -x build/bin/fray ]]; then
  echo "Opening the editor on the demo project (build/bin/fray with no argument; build/bin/fray $run/duel.frayscene plays the duel)."
  build/bin/fray "$lib/demo.frayproj"
else
  echo "No display: open the editor on the demo project later with build/bin/fray (headless: xvfb-run -a build/bin/fray --quit-after 30 --wait-analysis --screenshot shot.png); build/bin/fray $run/duel.frayscene plays the duel."
fi
