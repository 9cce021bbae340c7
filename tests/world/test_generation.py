"""Procedural houses: determinism, presets, conditions, validity checks, diversity."""

from __future__ import annotations

import hashlib
import json
import math
import subprocess
import sys
import time
from collections import Counter

import numpy as np
import pytest

from legent_gym.world.assets import registry
from legent_gym.world.generation import (
    PRESETS,
    GenerationError,
    HouseSpec,
    check_house,
    generate_house,
    parse_rooms,
)
from legent_gym.world.generation.dressing import BOOK_SHELVES, CUSHIONS
from legent_gym.world.generation.floorplan import WALL_THICKNESS
from legent_gym.world.generation.furnish import (
    HANG_ABOVE_FURNITURE,
    HANG_BELOW_CEILING,
    HANG_CENTRE,
    ROOM_SURFACE_PIECES,
    SUPPORTS,
)
from legent_gym.world.generation.small_objects import open_receptacle
from legent_gym.world.generation.validate import find_receptacle
from legent_gym.world.geometry import HANGING_HEIGHT, object_footprint, polygon_signed_area
from legent_gym.world.navigation import NavGrid
from legent_gym.world.scene import ObjectInstance, validate_scene

PRESET_ROOMS = {
    "OneRoom": [["bedroom"]],
    "TwoRoom": [["bedroom", "living_room"]],
    "FourRoom": [["bedroom", "living_room", "kitchen", "bathroom"]],
    "Apartment": PRESETS["Apartment"].room_options,
}
#: Set dressing resting on furniture: what it may rest on.
DRESSING_ON = {"shelved_book": set(BOOK_SHELVES), "cushion": set(CUSHIONS)}
PRIORITY = {"bedroom": {"bed"}, "living_room": {"sofa"}, "kitchen": {"fridge", "kitchen_counter"},
            "bathroom": {"toilet"}, "dining_room": {"dining_table"}, "office": {"desk"}}


def category(obj: ObjectInstance) -> str:
    return registry.describe(obj.asset).category


def counts(scene) -> Counter:
    return Counter(category(o) for o in scene.objects)


def per_surface(scene) -> Counter:
    """Small objects per receptacle (furniture id, receptacle index)."""
    out = Counter()
    for o in scene.objects:
        if o.kind == "interactable":
            found = find_receptacle(scene, scene.object(o.on), o, object_footprint(scene, o))
            assert found is not None
            out[(o.on, found[0])] += 1
    return out


# ---------------------------------------------------------------------------------------
# Determinism


@pytest.mark.parametrize("preset", list(PRESETS))
def test_same_seed_gives_identical_json_and_seeds_differ(preset):
    a = generate_house(3, preset).to_json()
    assert generate_house(3, preset).to_json() == a
    assert generate_house(4, preset).to_json() != a


def test_json_is_identical_across_processes_and_hash_seeds():
    code = ("import hashlib; from legent_gym.world.generation import generate_house; "
            "print(hashlib.sha256((generate_house(11, 'FourRoom').to_json() + "
            "generate_house(5, 'Apartment', require_on=[('apple', 'table')]).to_json()).encode()).hexdigest())")
    here = hashlib.sha256((generate_house(11, "FourRoom").to_json()
                           + generate_house(5, "Apartment", require_on=[("apple", "table")]).to_json()).encode())
    for hash_seed in ("1", "12345"):
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                             env={"PYTHONHASHSEED": hash_seed, "PATH": "/usr/bin:/bin"})
        assert out.stdout.strip() == here.hexdigest()


def test_floats_are_rounded_for_clean_json():
    scene = generate_house(0, "TwoRoom")
    for obj in scene.objects:
        assert all(round(v, 4) == v for v in obj.position)
    for room in scene.rooms:
        assert all(round(v, 4) == v for p in room.polygon for v in p)


# ---------------------------------------------------------------------------------------
# Presets and house structure


@pytest.mark.parametrize("preset", list(PRESETS))
def test_presets_generate_valid_houses(preset):
    n_seeds = 20 if preset in ("OneRoom", "TwoRoom") else 12
    for seed in range(n_seeds):
        scene = generate_house(seed, preset)
        validate_scene(scene)
        assert check_house(scene) == [], (preset, seed)
        assert [r.type for r in scene.rooms] in PRESET_ROOMS[preset]
        _check_structure(scene)


def _check_structure(scene) -> None:
    ids = [r.id for r in scene.rooms]
    # Room polygons counter-clockwise; together they cover the house without overlap.
    areas = [polygon_signed_area(r.polygon) for r in scene.rooms]
    assert all(a > 0 for a in areas)
    nav = NavGrid.from_scene(scene)
    cover = np.zeros(nav.shape, dtype=int)
    for room in scene.rooms:
        mask = np.zeros(nav.shape, dtype=bool)
        nav.raster.fill_polygon(mask, np.asarray(room.polygon))
        cover += mask
    assert cover.max() == 1
    # Walls: every segment once, shared ones between two rooms, outer ones with the exterior.
    segs = set()
    for w in scene.walls:
        key = tuple(sorted([tuple(w.start), tuple(w.end)]))
        assert key not in segs
        segs.add(key)
        assert w.start[0] == w.end[0] or w.start[1] == w.end[1]
        assert w.rooms[0] in ids and (w.rooms[1] in ids or w.rooms[1] == "exterior")
        assert w.height == 3.0 and w.thickness == 0.1
    perimeter = sum(w.length for w in scene.walls if w.rooms[1] == "exterior")
    inner = sum(w.length for w in scene.walls if w.rooms[1] != "exterior")
    room_perimeters = sum(math.dist(p, q) for r in scene.rooms for p, q in zip(r.polygon, r.polygon[1:] + r.polygon[:1]))
    assert room_perimeters == pytest.approx(perimeter + 2 * inner, abs=1e-3)
    # Doors: interior ones in shared walls, one front door, all open, away from wall ends.
    walls = {w.id: w for w in scene.walls}
    assert sum("exterior" in d.connects for d in scene.doors) == 1
    for d in scene.doors:
        assert d.openness == 1.0
        assert sorted(d.connects) == sorted(walls[d.wall].rooms)
        assert d.offset - d.width / 2 >= 0.3 and d.offset + d.width / 2 <= walls[d.wall].length - 0.3
        if d.leaf:
            assert 0.8 <= d.width <= 1.0
    # Rooms get their priority furniture.
    by_room = {}
    for o in scene.objects:
        by_room.setdefault(o.room, set()).add(category(o))
    for room in scene.rooms:
        assert PRIORITY.get(room.type, set()) <= by_room.get(room.id, set()), room.type
    # Objects: ids 0..N-1; furniture on the floor, axis-aligned; small objects on something.
    assert [o.id for o in scene.objects] == list(range(len(scene.objects)))
    for o in scene.objects:
        model = registry.describe(o.asset)
        if model.pickupable:
            assert o.kind == "interactable" and o.on is not None
        elif o.on is None:
            hangs = model.placement == "hanging" and o.position[2] >= HANGING_HEIGHT
            kind = "covering" if model.placement == "floor" else "static"
            assert o.kind == kind and (o.position[2] == 0.0 or hangs) and o.rotation[2] % 90 == 0
        elif category(o) in DRESSING_ON:
            assert category(scene.object(o.on)) in DRESSING_ON[category(o)] and o.kind == "static"
        else:
            assert category(scene.object(o.on)) in SUPPORTS[category(o)]
    # Style and lights.
    assert len(scene.lights) == len(scene.rooms)
    assert all(light.position[2] == pytest.approx(2.8) for light in scene.lights)
    assert len({(r.floor.material, r.floor.rgba) for r in scene.rooms}) >= min(2, len(scene.rooms))


def test_small_objects_at_most_three_per_surface_and_inside_receptacles():
    for seed in range(6):
        scene = generate_house(seed, "FourRoom", density=3.0)
        surfaces = per_surface(scene)
        assert surfaces and max(surfaces.values()) <= 3
        for o in scene.objects:
            if o.kind != "interactable":
                continue
            # Small yaw only, relative to the furniture.
            rel = (o.rotation[2] - scene.object(o.on).rotation[2] + 180) % 360 - 180
            assert abs(rel) <= 15.0 + 1e-6
        assert check_house(scene) == []  # includes "inside a receptacle" and no overlap


def test_surfaces_behind_closed_doors_get_no_small_objects():
    """open_receptacle: a surface is open unless closed doors span its width (or it lies in
    a drawer); a tv stand's middle shelf stays open between two sides with doors."""
    seen = set()
    for asset in ("tv_stand", "kitchen_counter", "sideboard", "desk", "fridge", "storage_cabinet"):
        for v in range(30):
            m = registry.make(asset, v)
            doors = any(lk.joint is not None and lk.joint.kind == "hinge" for lk in m.links)
            for r in m.receptacles:
                expected = r.link == "base" and (r.name in ("top", "shelf") or not doors)
                assert open_receptacle(m, r) == expected, (asset, v, r.name)
                seen.add((asset, r.name, expected))
    assert {("tv_stand", "shelf", True), ("tv_stand", "shelf_left", False), ("kitchen_counter", "shelf_0", False),
            ("kitchen_counter", "top", True), ("sideboard", "shelf_0", False)} <= seen


def test_density_and_max_per_surface_conditions():
    sparse = sum(o.kind == "interactable" for s in range(4) for o in generate_house(s, "TwoRoom", density=0.3).objects)
    dense = sum(o.kind == "interactable" for s in range(4) for o in generate_house(s, "TwoRoom", density=2.5).objects)
    assert dense > sparse
    scene = generate_house(0, "TwoRoom", density=3.0, max_per_surface=1)
    assert max(per_surface(scene).values()) == 1
    assert all(o.kind != "interactable" for o in generate_house(0, "TwoRoom", density=0.0).objects)


def test_spawns_reachable_and_apart():
    for seed in range(6):
        scene = generate_house(seed, "TwoRoom")
        nav = NavGrid.from_scene(scene)
        assert nav.is_walkable(scene.agent.position) and nav.is_walkable(scene.user.position)
        assert nav.reachable(scene.agent.position, scene.user.position)
        assert math.dist(scene.agent.position, scene.user.position) >= 1.5
    for seed in range(4):
        scene = generate_house(seed, "OneRoom", min_user_distance=3.0)
        assert math.dist(scene.agent.position, scene.user.position) >= 3.0
    assert generate_house(0, "OneRoom", user=False).user is None


def test_every_piece_has_a_standing_point_from_the_agent():
    scene = generate_house(2, "Apartment")
    nav = NavGrid.from_scene(scene)
    for o in scene.objects:
        if o.on is None:
            p = nav.standing_point(o.id, reach=1.0, start=scene.agent.position)
            assert p is not None and nav.reachable(p, scene.agent.position)


# ---------------------------------------------------------------------------------------
# Specs and conditions


def test_room_mixes_from_strings_and_lists():
    assert parse_rooms("bedroom") == ["bedroom"]
    assert parse_rooms("bedroom + living room") == ["bedroom", "living_room"]
    assert parse_rooms("2 bed 1 bath") == ["bedroom", "bedroom", "bathroom"]
    assert parse_rooms("kitchen, living room, bathroom") == ["kitchen", "living_room", "bathroom"]
    assert [r.type for r in generate_house(0, "2 bed 1 bath").rooms] == ["bedroom", "bedroom", "bathroom"]
    assert [r.type for r in generate_house(0, ["office", "hallway", "dining_room"]).rooms] == [
        "office", "hallway", "dining_room"]
    assert [r.type for r in generate_house(0, rooms="kitchen, living room").rooms] == ["kitchen", "living_room"]
    assert len(generate_house(1, n_rooms=5).rooms) == 5
    assert len(generate_house(1, {"rooms": ["bedroom"], "n_rooms": 3}).rooms) == 3
    spec = HouseSpec(rooms="bedroom + office", density=0.5)
    assert [r.type for r in generate_house(0, spec).rooms] == ["bedroom", "office"]


def test_room_sizes_are_plausible():
    sizes: dict[str, list[float]] = {}
    for seed in range(10):
        for room in generate_house(seed, "FourRoom").rooms:
            sizes.setdefault(room.type, []).append(polygon_signed_area(room.polygon))
    assert np.mean(sizes["bathroom"]) < np.mean(sizes["bedroom"]) < np.mean(sizes["living_room"])
    assert min(sizes["bathroom"]) >= 3.5 and max(sizes["living_room"]) <= 60


def test_houses_are_not_always_square():
    ratios = []
    for seed in range(10):
        (x0, y0), (x1, y1) = generate_house(seed, "TwoRoom").bounds()
        ratios.append((x1 - x0) / (y1 - y0))
    assert max(abs(math.log(r)) for r in ratios) > 0.2


def test_orange_on_sofa():
    for seed, spec in ((0, "OneRoom"), (1, "TwoRoom")):
        for cond in ({"require_on": [("orange", "sofa")]}, {"require_on": "an orange on the sofa"},
                     {"require": ["orange on sofa"]}):
            scene = generate_house(seed, spec, **cond)
            assert any(category(o) == "orange" and o.on is not None and category(scene.object(o.on)) == "sofa"
                       for o in scene.objects), (spec, cond)


def test_counts_are_exact():
    scene = generate_house(0, "TwoRoom", object_counts={"apple": 2, "orange": 0, "chair": 3})
    c = counts(scene)
    assert c["apple"] == 2 and c["orange"] == 0 and c["chair"] == 3
    scene = generate_house(1, "FourRoom", object_counts={"cola": 4}, require_on=[("cola_can", "countertop")])
    assert counts(scene)["cola_can"] == 4


def test_required_furniture_and_rooms():
    scene = generate_house(0, "TwoRoom", require=["sofa", "dresser", "bookshelf"])
    c = counts(scene)
    assert c["sofa"] >= 1 and c["dresser"] >= 1 and c["bookshelf"] >= 1
    scene = generate_house(2, require_on=[("orange", "bathtub")], n_rooms=3)
    assert "bathroom" in [r.type for r in scene.rooms]
    assert any(category(o) == "orange" and category(scene.object(o.on)) == "bathtub"
               for o in scene.objects if o.on is not None)


def test_area_condition():
    for seed in range(3):
        scene = generate_house(seed, "TwoRoom", area=(30, 45))
        assert 30 <= sum(polygon_signed_area(r.polygon) for r in scene.rooms) <= 45


@pytest.mark.parametrize(("kwargs", "words"), [
    ({"object_counts": {"bed": 50}}, ["50 'bed'", "object_counts"]),
    ({"require_on": [("orange", "bathtub")]}, ["'orange on bathtub'", "bathroom"]),
    ({"require_on": ["orange on spaceship"]}, ["spaceship", "known categories", "sofa"]),
    ({"require": ["unicorn"]}, ["unicorn", "known categories"]),
    ({"object_counts": {"unicorn": 1}}, ["unicorn", "known categories"]),
    ({"area": (5, 8)}, ["area"]),
    ({"object_counts": {"apple": 300}}, ["300 'apple'", "object_counts"]),
    ({"min_user_distance": 40.0}, ["min_user_distance"]),
    ({"require_on": [("sofa", "bed")]}, ["'sofa on bed'", "not a small object"]),
])
def test_impossible_conditions_raise_naming_the_condition(kwargs, words):
    t = time.perf_counter()
    with pytest.raises(GenerationError) as err:
        generate_house(0, "OneRoom", **kwargs)
    assert time.perf_counter() - t < 10.0
    for w in words:
        assert w in str(err.value), (w, str(err.value))


def test_bad_arguments():
    with pytest.raises(TypeError, match="bogus"):
        generate_house(0, "OneRoom", bogus=1)
    with pytest.raises(GenerationError, match="spaceship"):
        generate_house(0, "spaceship")
    with pytest.raises(GenerationError, match="rooms must list room types.*n_rooms"):
        generate_house(0, rooms=2)  # a count where the room list goes
    assert issubclass(GenerationError, ValueError)
    # None means "not given".
    assert generate_house(0, "OneRoom", require=None, n_rooms=None).to_json() == generate_house(0, "OneRoom").to_json()


# ---------------------------------------------------------------------------------------
# The checker finds what is wrong


def test_check_house_reports_problems():
    scene = generate_house(0, "TwoRoom")
    assert check_house(scene) == []
    furniture = [o for o in scene.objects if o.on is None]
    # Two pieces on top of each other.
    broken = scene.model_copy(deep=True)
    broken.objects[furniture[1].id].position = furniture[0].position
    broken.objects[furniture[1].id].rotation = furniture[0].rotation
    assert any("overlap" in p for p in check_house(broken))
    # A closed door between the rooms: the other room is cut off.
    closed = scene.model_copy(deep=True)
    for d in closed.doors:
        if "exterior" not in d.connects:
            d.openness = 0.0
    problems = check_house(closed)
    assert any("reached" in p or "reachable" in p for p in problems)
    # A piece in a doorway.
    blocked = scene.model_copy(deep=True)
    door = next(d for d in blocked.doors if "exterior" not in d.connects)
    wall = next(w for w in blocked.walls if w.id == door.wall)
    start, end = np.asarray(wall.start), np.asarray(wall.end)
    centre = start + (end - start) / wall.length * door.offset
    blocked.objects[furniture[0].id].position = (float(centre[0]), float(centre[1]), 0.0)
    assert any(door.id in p for p in check_house(blocked))
    # Agent spawn inside furniture.
    inside = scene.model_copy(deep=True)
    fp = object_footprint(inside, furniture[0])
    inside.agent.position = tuple(fp.mean(axis=0))
    assert any("agent spawn" in p for p in check_house(inside))


# ---------------------------------------------------------------------------------------
# Large sweeps (pytest -m slow)


def _layout_key(scene) -> str:
    rooms = [(r.type, tuple(map(tuple, r.polygon))) for r in scene.rooms]
    return hashlib.md5(json.dumps(rooms).encode()).hexdigest()


def _grid_key(scene) -> str:
    """The floor plan up to cell size: coordinates replaced by their rank."""
    xs = sorted({p[0] for r in scene.rooms for p in r.polygon})
    ys = sorted({p[1] for r in scene.rooms for p in r.polygon})
    rooms = [(r.type, [(xs.index(x), ys.index(y)) for x, y in r.polygon]) for r in scene.rooms]
    return json.dumps(rooms)


@pytest.mark.slow
@pytest.mark.parametrize("preset", list(PRESETS))
def test_thousand_seeds_valid_deterministic_and_diverse(preset):
    layouts, grids, object_sets, furniture_sets = set(), set(), set(), set()
    times = []
    for seed in range(1000):
        t = time.perf_counter()
        scene = generate_house(seed, preset)
        times.append(time.perf_counter() - t)
        assert check_house(scene) == [], (preset, seed)
        if seed % 50 == 0:
            assert generate_house(seed, preset).to_json() == scene.to_json()
        layouts.add(_layout_key(scene))
        grids.add(_grid_key(scene))
        object_sets.add(tuple(sorted(counts(scene).items())))
        furniture_sets.add(tuple(sorted((category(o), o.room) for o in scene.objects if o.on is None)))
    print(f"\n{preset}: 1000 houses, {len(layouts)} distinct layouts ({len(grids)} up to cell size), "
          f"{len(object_sets)} distinct object "
          f"sets, {len(furniture_sets)} distinct furniture sets; median {np.median(times) * 1e3:.0f} ms, "
          f"max {max(times) * 1e3:.0f} ms per house")
    assert len(layouts) > 900 and len(object_sets) > 500


ROOM_SURFACE_PIECES_KITCHEN = {rule.category for rule in ROOM_SURFACE_PIECES["kitchen"]}


def test_kitchen_counters_hold_appliances():
    """ROOM_SURFACE_PIECES: kitchens stand a microwave, coffee machine or toaster on a free
    counter, one piece per counter."""
    standing = []
    for seed in range(20):
        scene = generate_house(seed, "FourRoom")
        on_counters = [o for o in scene.objects if o.on is not None
                       and registry.describe(scene.object(o.on).asset).category == "kitchen_counter"
                       and registry.describe(o.asset).category in ROOM_SURFACE_PIECES_KITCHEN]
        assert len({o.on for o in on_counters}) == len(on_counters)
        standing += on_counters
    assert {registry.describe(o.asset).category for o in standing} == ROOM_SURFACE_PIECES_KITCHEN


def test_pictures_hang_on_free_walls_above_the_furniture():
    """WALL_DECOR: pictures hang with their backs on a wall, at eye level or above what stands
    in front of them, below the ceiling, clear of windows and doors; they block no floor (the
    navigation grid is the same without them) and every house is still valid."""
    hung = 0
    for seed in range(8):
        scene = generate_house(seed, "FourRoom")
        pictures = [o for o in scene.objects if o.asset == "wall_picture"]
        hung += len(pictures)
        ceiling = max(w.height for w in scene.walls)
        others = [o for o in scene.objects if o.asset != "wall_picture"]
        without = scene.model_copy(update={"objects": others})
        assert np.array_equal(NavGrid.from_scene(scene).walkable, NavGrid.from_scene(without).walkable)
        for pic in pictures:
            size = registry.make(pic.asset, pic.variant).size
            assert pic.position[2] >= HANGING_HEIGHT and pic.position[2] + size[2] <= ceiling - HANG_BELOW_CEILING + 1e-4
            assert pic.position[2] + size[2] / 2 >= HANG_CENTRE - 1e-4  # (positions rounded to 0.1 mm)
            foot = object_footprint(scene, pic)
            room = np.asarray(scene.room(pic.room).polygon)
            # The back lies on the room's wall face (half a wall in from its outline).
            gaps = [_distance_to_outline(corner, room) for corner in foot]
            assert min(gaps) < WALL_THICKNESS / 2 + 0.02
            for opening in [*scene.doors, *scene.windows]:
                assert not _overlaps_opening(scene, foot, opening), f"seed {seed}: {pic.id} over {opening.id}"
            for obj in others:
                if obj.on is None and obj.room == pic.room and obj.kind == "static":
                    top = obj.position[2] + registry.make(obj.asset, obj.variant).size[2]
                    other = object_footprint(scene, obj)
                    if _boxes_overlap(foot, other, 0.05):
                        assert pic.position[2] >= top + HANG_ABOVE_FURNITURE - 1e-4
        assert not check_house(scene)
    assert hung >= 16  # most rooms of most houses have pictures


def _distance_to_outline(point, polygon) -> float:
    a, b = polygon, np.roll(polygon, -1, axis=0)
    ab = b - a
    t = np.clip(((point - a) * ab).sum(axis=1) / (ab * ab).sum(axis=1), 0, 1)
    return float(np.hypot(*(a + t[:, None] * ab - point).T).min())


def _boxes_overlap(a, b, grow: float) -> bool:
    (ax0, ay0), (ax1, ay1) = np.min(a, axis=0) - grow, np.max(a, axis=0) + grow
    (bx0, by0), (bx1, by1) = np.min(b, axis=0), np.max(b, axis=0)
    return ax0 < bx1 and bx0 < ax1 and ay0 < by1 and by0 < ay1


def _overlaps_opening(scene, foot, opening) -> bool:
    """Whether a footprint lies over a door or window: near its wall and within its span."""
    wall = scene.wall(opening.wall)
    start, end = np.asarray(wall.start), np.asarray(wall.end)
    u = (end - start) / np.hypot(*(end - start))
    along = (np.asarray(foot) - start) @ u
    across = np.abs((np.asarray(foot) - start) @ np.array([-u[1], u[0]]))
    lo, hi = opening.offset - opening.width / 2, opening.offset + opening.width / 2
    return bool(across.min() < wall.thickness and along.max() > lo and along.min() < hi)
