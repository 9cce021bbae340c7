#!/usr/bin/env bash
# Set everything up, then run the main job: build the example houses and render them to PNG.
set -euo pipefail
cd "$(dirname "$0")/.."
LEGENT_EXTRAS="${LEGENT_EXTRAS:-dev}" bash scripts/setup.sh
mkdir -p out
for scene in examples/scenes/*.json; do
  name="$(basename "$scene" .json)"
  .venv/bin/legent-gym validate "$scene"
  for view in topdown agent user; do
    .venv/bin/legent-gym render "$scene" --view "$view" --out "out/${name}_${view}.png" --size 512 --profile pretty
  done
done
if .venv/bin/python -c "import legent_gym.world.generation" 2>/dev/null; then
  .venv/bin/legent-gym generate --preset TwoRoom --seed 3 --out out/generated_TwoRoom_3.json --map out/generated_TwoRoom_3.png
fi
echo "done: images in out/"
echo "next, play in the browser (as the user; the expert drives the agent):"
echo "  LEGENT_EXTRAS=dev,multiagent,play bash scripts/setup.sh && .venv/bin/legent-gym play Legent/ComeHere-TwoRoom-v0"
