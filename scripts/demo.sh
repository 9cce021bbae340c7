#!/usr/bin/env bash
# Set everything up, then run the main job: build the example houses and render them to PNG,
# generate a house, and collect expert episodes in it (Minari dataset, LEGENT's format,
# H.264 video with the path seen from above).
set -euo pipefail
cd "$(dirname "$0")/.."
LEGENT_EXTRAS="${LEGENT_EXTRAS:-dev,data}" bash scripts/setup.sh
mkdir -p out
for scene in examples/scenes/*.json; do
  name="$(basename "$scene" .json)"
  .venv/bin/legent-gym validate "$scene"
  for view in topdown agent user; do
    .venv/bin/legent-gym render "$scene" --view "$view" --out "out/${name}_${view}.png" --size 512 --profile pretty
  done
done
.venv/bin/legent-gym generate --preset TwoRoom --seed 3 --out out/generated_TwoRoom_3.json --map out/generated_TwoRoom_3.png
# Expert demonstrations in that house: 3 Come Here episodes, each with its own spawns.
.venv/bin/legent-gym collect Legent/ComeHere-TwoRoom-v0 --episodes 3 --out out/collect --format minari,legent,video \
  --env-kwargs '{"scene": "out/generated_TwoRoom_3.json", "episodes_per_house": 3}' --quiet
echo "done: images in out/, expert episodes in out/collect/ (minari/, legent/, video/*.mp4 and *_map.png)"
echo "next, play in the browser (as the user; the expert drives the agent):"
echo "  LEGENT_EXTRAS=dev,multiagent,play bash scripts/setup.sh && .venv/bin/legent-gym play Legent/ComeHere-TwoRoom-v0"
