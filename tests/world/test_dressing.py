"""Set dressing (legent_gym/world/generation/dressing.py): books on shelves, rugs and mats,
wall cabinets and hoods, curtains and cushions, and what they add to a house's looks.
"""

from __future__ import annotations

import statistics
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from legent_gym.world.assets import registry
from legent_gym.world.generation import generate_house
from legent_gym.world.generation.dressing import (
    BOOK_SHELVES,
    CABINET_BOTTOM,
    CUSHIONS,
    ROW_MIN,
    UNDER_CABINETS,
    UNDER_HOOD,
)
from legent_gym.world.generation.validate import find_receptacle
from legent_gym.world.geometry import HANGING_HEIGHT, object_footprint, points_in_polygon
from legent_gym.world.navigation import NavGrid

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from variety import look  # noqa: E402  (what benchmarks/variety.py counts as one look)

#: Distinct looks per FourRoom house before the set dressing and the wider library, over
#: seeds 0-99 (``python benchmarks/variety.py --houses 100 --layouts FourRoom`` at 7b44fdc).
LOOKS_BEFORE = 33.89
SEEDS = range(12)


@pytest.fixture(scope="module")
def houses():
    return [generate_house(seed, "FourRoom") for seed in SEEDS]


def _category(scene, obj) -> str:
    return registry.describe(obj.asset).category


def test_every_kind_of_dressing_appears(houses):
    seen = Counter(o.asset for scene in houses for o in scene.objects)
    for asset in ("shelved_book", "rug", "wall_cabinet", "range_hood", "curtain", "cushion"):
        assert seen[asset] > 0, asset


def test_books_stand_in_rows_on_open_shelves(houses):
    for scene in houses:
        rows = Counter()
        for o in scene.objects:
            if o.asset != "shelved_book":
                continue
            host = scene.object(o.on)
            assert _category(scene, host) in BOOK_SHELVES and o.kind == "static"
            found = find_receptacle(scene, host, o, None)
            assert found is not None
            rec = registry.make(host.asset, host.variant).receptacles[found[0]]
            assert registry.make(o.asset, o.variant).size[2] <= rec.clearance  # under the shelf above
            assert o.rotation[2] == host.rotation[2]  # spines to the front
            rows[(o.on, found[0])] += 1
        assert all(n >= ROW_MIN for n in rows.values())


def test_rugs_cover_the_floor_and_block_nothing(houses):
    for scene in houses:
        rugs = [o for o in scene.objects if o.asset == "rug"]
        for rug in rugs:
            assert rug.kind == "covering" and rug.on is None and rug.position[2] == 0.0
            room = next(r for r in scene.rooms if r.id == rug.room)
            assert points_in_polygon(object_footprint(scene, rug), np.asarray(room.polygon)).all()
        if rugs:
            without = scene.model_copy(update={"objects": [o for o in scene.objects if o.asset != "rug"]})
            assert np.array_equal(NavGrid.from_scene(scene).walkable, NavGrid.from_scene(without).walkable)


def test_kitchens_get_wall_cabinets_in_one_style_and_a_hood_over_the_stove(houses):
    kitchens = 0
    for scene in houses:
        cabinets = [o for o in scene.objects if o.asset == "wall_cabinet"]
        hoods = [o for o in scene.objects if o.asset == "range_hood"]
        kitchen = next(r.id for r in scene.rooms if r.type == "kitchen")
        kitchens += bool(cabinets)
        assert len({o.variant for o in cabinets}) <= 1
        for o in cabinets + hoods:
            assert o.room == kitchen and o.position[2] >= CABINET_BOTTOM - 0.5 >= HANGING_HEIGHT
            top = o.position[2] + registry.make(o.asset, o.variant).size[2] * o.scale[2]
            assert top < scene.walls[0].height
            # Something of the kind it hangs over stands under it.
            under = {UNDER_HOOD} if o.asset == "range_hood" else set(UNDER_CABINETS)
            below = [p for p in scene.objects if p.room == kitchen and p.on is None and _category(scene, p) in under
                     and np.abs(np.asarray(p.position[:2]) - o.position[:2]).max() < 1.0]
            assert below, o
    assert kitchens >= len(houses) // 2


def test_curtains_hang_beside_windows_within_reach(houses):
    for scene in houses:
        nav = NavGrid.from_scene(scene)
        for o in scene.objects:
            if o.asset != "curtain":
                continue
            assert o.on is None and o.position[2] >= HANGING_HEIGHT
            near = [w for w in scene.windows if scene.wall(w.wall).rooms[0] == o.room]
            assert near
            assert nav.standing_point(o.id, reach=1.0, start=scene.agent.position) is not None


def test_cushions_lean_on_seats(houses):
    seats = 0
    for scene in houses:
        for o in scene.objects:
            if o.asset == "cushion":
                assert _category(scene, scene.object(o.on)) in CUSHIONS and o.kind == "static"
                seats += 1
    assert seats


def test_a_hundred_houses_show_three_times_the_looks_and_ninety_types():
    """The issue's acceptance: over 100 FourRoom houses, >= 90 asset types appear, and the
    mean number of distinct looks per house is at least 3x what it was before."""
    looks, types = [], set()
    for seed in range(100):
        scene = generate_house(seed, "FourRoom")
        looks.append(len({look(o.asset, o.variant) for o in scene.objects}))
        types |= {o.asset for o in scene.objects}
    assert len(types) >= 90
    assert statistics.fmean(looks) >= 3 * LOOKS_BEFORE
