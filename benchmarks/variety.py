"""What generated houses hold: objects, asset types and distinct looks per house.

    python benchmarks/variety.py [--houses 100] [--layouts OneRoom,TwoRoom,FourRoom]
    python benchmarks/compare.py --before REV -- variety.py   # before/after a change

For each layout, over seeds 0..N-1: the mean number of objects per house, of small
(interactable) objects, of distinct looks per house (an asset type, its variant and the
materials of its parts: what the camera can tell apart), and how many asset types appear
in any of the N houses, against the built-in library's count. Deterministic: the same
commit prints the same table. The last row is FourRoom's (what ``compare.py`` reads).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys

from benchmarks_common import write_report

import legent_gym  # noqa: F401
from legent_gym.world import generation
from legent_gym.world.assets import registry
from legent_gym.world.generation import generate_house


def look(asset: str, variant: int) -> tuple:
    """An object's look: its asset type, variant and the materials of its parts."""
    model = registry.make(asset, variant)
    return asset, variant, tuple(sorted({p.material for link in model.links for p in link.parts}))


def survey(layout: str, houses: int) -> dict:
    objects, small, looks, types = [], [], [], set()
    for seed in range(houses):
        scene = generate_house(seed, layout)
        objects.append(len(scene.objects))
        small.append(sum(o.kind == "interactable" for o in scene.objects))
        looks.append(len({look(o.asset, o.variant) for o in scene.objects}))
        types |= {o.asset for o in scene.objects}
    return {"objects": statistics.fmean(objects), "small": statistics.fmean(small),
            "looks": statistics.fmean(looks), "types": len(types)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--houses", type=int, default=100)
    parser.add_argument("--layouts", default="OneRoom,TwoRoom,FourRoom")
    parser.add_argument("--json", metavar="OUT", help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    load_before = os.getloadavg()[0]
    library = len(registry.asset_ids(builtin=True))
    pickupable = sum(registry.describe(a).pickupable for a in registry.asset_ids(builtin=True))
    # (commits before the generator had a version number: 1, for a before/after run)
    version = getattr(generation, "GENERATOR_VERSION", 1)
    print(f"generator version {version}; built-in asset types {library} ({pickupable} pickupable); "
          f"{args.houses} houses per layout")
    print(f"{'layout':>9} {'objects':>8} {'small':>6} {'looks':>6} {'types':>6}")
    rows = {}
    for layout in args.layouts.split(","):
        r = rows[layout] = survey(layout, args.houses)
        print(f"{layout:>9} {r['objects']:>8.2f} {r['small']:>6.2f} {r['looks']:>6.2f} {r['types']:>6d}")
    if args.json:
        write_report(args.json, args, rows, load_before)
    return 0


if __name__ == "__main__":
    sys.exit(main())
