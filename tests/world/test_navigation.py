"""NavGrid: walkable floor, paths, geodesic distances, doors, standing points, top-down maps."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from legent_gym.world.assets import registry
from legent_gym.world.geometry import object_footprint
from legent_gym.world.navigation import NavGrid
from legent_gym.world.scene import Door, ObjectInstance, Room, Scene, Spawn, Wall

RADIUS = 0.25


def two_room_scene(*, openness: float = 1.0, leaf: bool = True, furniture: bool = True) -> Scene:
    """Two 4 x 4 m rooms side by side (x in [0, 4] and [4, 8]) with a door in the shared
    wall at y = 2; a dresser against the shared wall in room a, a wardrobe in room b."""
    rooms = [Room(id="a", type="bedroom", name="bedroom", polygon=[(0, 0), (4, 0), (4, 4), (0, 4)]),
             Room(id="b", type="living_room", name="living room", polygon=[(4, 0), (8, 0), (8, 4), (4, 4)])]
    outer = [((0, 0), (4, 0), "a"), ((4, 0), (8, 0), "b"), ((8, 0), (8, 4), "b"), ((8, 4), (4, 4), "b"),
             ((4, 4), (0, 4), "a"), ((0, 4), (0, 0), "a")]
    walls = [Wall(id="shared", start=(4, 0), end=(4, 4), rooms=["a", "b"])]
    walls += [Wall(id=f"outer_{k}", start=s, end=e, rooms=[r, "exterior"]) for k, (s, e, r) in enumerate(outer)]
    doors = [Door(id="door", wall="shared", offset=2.0, width=0.9, leaf=leaf, openness=openness,
                  connects=["a", "b"])]
    objects = []
    if furniture:
        b = registry.make("dresser", 0).bounds()
        # Back to the shared wall (front facing -x: yaw 90), in the upper part of room a.
        x = 4.0 - 0.05 - 0.02 - b[1, 1]
        objects.append(ObjectInstance(id=0, asset="dresser", position=(x, 3.9 - b[1, 0], 0.0),
                                      rotation=(0, 0, 90), room="a"))
        w = registry.make("wardrobe", 0).bounds()
        # In the middle of room b, across the straight line from a's corner to b's corner.
        objects.append(ObjectInstance(id=1, asset="wardrobe", position=(6.0, 2.0, 0.0), rotation=(0, 0, 0),
                                      room="b"))
        assert w[1, 0] - w[0, 0] < 2.0
    return Scene(rooms=rooms, walls=walls, doors=doors, objects=objects, agent=Spawn(position=(1.0, 1.0)))


@pytest.fixture(scope="module")
def scene() -> Scene:
    return two_room_scene()


@pytest.fixture(scope="module")
def nav(scene: Scene) -> NavGrid:
    return NavGrid.from_scene(scene, agent_radius=RADIUS)


def _samples(path, step=0.01):
    for p, q in zip(path, path[1:]):
        n = max(1, int(math.dist(p, q) / step))
        for t in np.linspace(0.0, 1.0, n + 1):
            yield (p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t)


def test_walkable_respects_walls_furniture_and_radius(scene: Scene, nav: NavGrid):
    assert nav.is_walkable((1.0, 1.0))
    assert not nav.is_walkable((4.0, 1.0))  # in the shared wall
    assert not nav.is_walkable((0.1, 2.0))  # too close to the outer wall for the radius
    assert not nav.is_walkable((-1.0, 2.0))  # outside the house
    assert not nav.is_walkable((6.0, 2.0))  # inside the wardrobe
    assert nav.is_walkable((4.0, 2.0))  # in the open doorway


def test_path_avoids_furniture_and_has_few_corners(nav: NavGrid):
    start, goal = (1.0, 0.6), (7.4, 3.4)
    path = nav.path(start, goal)
    assert path[0] == start and path[-1] == goal
    assert all(nav.is_walkable(p) for p in _samples(path))
    assert len(path) <= 6, path


def test_geodesic_distance_is_at_least_the_straight_line(nav: NavGrid):
    rng = np.random.default_rng(0)
    cells = np.argwhere(nav.walkable)
    for _ in range(30):
        a = nav.to_world(cells[rng.integers(len(cells))])
        b = nav.to_world(cells[rng.integers(len(cells))])
        assert nav.distance(a, b) >= math.dist(a, b) - 1e-9
    # In open floor with a clear line, the geodesic distance is the straight one.
    assert nav.distance((0.8, 0.8), (2.6, 1.2)) == pytest.approx(math.dist((0.8, 0.8), (2.6, 1.2)), rel=1e-6)


def test_distance_field_is_cached_and_consistent(nav: NavGrid):
    goal = (7.0, 1.0)
    field = nav.distance_field(goal)
    assert field.shape == nav.shape
    assert field[nav.to_cell(goal)] == 0.0
    assert np.isinf(field[~nav.walkable]).all()
    start = (1.0, 1.0)
    grid_d = field[nav.to_cell(start)]
    # The grid distance (8-connected) is an upper bound of the string-pulled one.
    assert nav.distance(start, goal) <= grid_d + 1e-9
    assert nav.distance_field(goal) is not field  # a fresh array each call, same values
    assert np.array_equal(nav.distance_field(goal), field)


def test_closed_door_blocks_and_open_door_or_archway_passes():
    closed = NavGrid.from_scene(two_room_scene(openness=0.0))
    assert not closed.reachable((1.0, 1.0), (7.0, 1.0))
    assert closed.path((1.0, 1.0), (7.0, 1.0)) == []
    assert math.isinf(closed.distance((1.0, 1.0), (7.0, 1.0)))
    assert not closed.is_walkable((4.0, 2.0))
    ajar = NavGrid.from_scene(two_room_scene(openness=0.6))
    assert ajar.reachable((1.0, 1.0), (7.0, 1.0))
    archway = NavGrid.from_scene(two_room_scene(openness=0.0, leaf=False))
    assert archway.reachable((1.0, 1.0), (7.0, 1.0))
    path = archway.path((1.0, 1.0), (7.0, 1.0))
    assert all(archway.is_walkable(p) for p in _samples(path))


def test_nearest_walkable_snaps_out_of_obstacles(nav: NavGrid):
    inside = (6.0, 2.0)  # the wardrobe
    snapped = nav.nearest_walkable(inside)
    assert snapped is not None and nav.is_walkable(snapped)
    assert math.dist(snapped, inside) < 1.5
    assert nav.nearest_walkable((1.0, 1.0)) == (1.0, 1.0)
    path = nav.path(inside, (1.0, 1.0))
    assert path and nav.is_walkable(path[0])


def test_standing_point_is_within_reach_and_on_the_objects_side_of_the_wall(scene: Scene, nav: NavGrid):
    dresser = object_footprint(scene, scene.object(0))
    for start in (None, (7.0, 1.0), (1.0, 1.0)):
        p = nav.standing_point(0, reach=1.0, start=start)
        assert p is not None and nav.is_walkable(p)
        # Room b's floor is closer to the dresser's back, but the wall is in between.
        assert p[0] < 4.0
        nearest = _closest(dresser, np.asarray(p))
        assert math.dist(nearest, p) <= 1.0 + 1e-9
    from_b = nav.standing_point(0, start=(7.0, 1.0))
    near = nav.standing_point(0)
    assert from_b is not None and near is not None
    assert nav.distance((7.0, 1.0), from_b) <= nav.distance((7.0, 1.0), near) + 1e-6
    assert nav.standing_point(1, reach=1.0) is not None  # the wardrobe, from room b


def _closest(corners: np.ndarray, p: np.ndarray) -> np.ndarray:
    lo, hi = corners.min(axis=0), corners.max(axis=0)  # axis-aligned here
    return np.clip(p, lo, hi)


def test_unreachable_standing_point_is_none():
    nav = NavGrid.from_scene(two_room_scene(openness=0.0))
    assert nav.standing_point(1, start=(1.0, 1.0)) is None  # the wardrobe is behind a closed door


def test_path_queries_are_walkable_and_do_not_depend_on_the_cache(scene: Scene, nav: NavGrid):
    """40 random queries (more goals than the 32-field cache holds, so fields are evicted and
    recomputed): each path starts and ends at its query points, stays on walkable floor, is
    no longer than the 8-connected grid distance, and equals the path of a fresh grid that
    has cached nothing."""
    rng = np.random.default_rng(1)
    cells = np.argwhere(nav.walkable)
    pairs = [(nav.to_world(cells[rng.integers(len(cells))]), nav.to_world(cells[rng.integers(len(cells))]))
             for _ in range(40)]
    warm = [nav.path(a, b) for a, b in pairs] + [nav.path(a, b) for a, b in pairs]
    for (a, b), first, again in zip(pairs, warm[:40], warm[40:]):
        cold = NavGrid.from_scene(scene, agent_radius=RADIUS).path(a, b)
        assert first == again == cold, (a, b)
        if nav.reachable(a, b):
            assert first[0] == pytest.approx(a, abs=1e-6) and first[-1] == pytest.approx(b, abs=1e-6)
            assert all(nav.is_walkable(p) for p in _samples(first))
            length = sum(math.dist(p, q) for p, q in zip(first, first[1:]))
            assert length <= nav.distance_field(b)[nav.to_cell(a)] + 1e-9
        else:
            assert first == []


@pytest.mark.slow
def test_path_query_under_5ms_on_generated_two_room_houses():
    from legent_gym.world.generation import generate_house

    times = []
    for seed in range(10):
        house = generate_house(seed, "TwoRoom")
        nav = NavGrid.from_scene(house).precompute()
        rng = np.random.default_rng(seed)
        cells = np.argwhere(nav.labels == nav.component(house.agent.position))
        for _ in range(20):
            a = nav.to_world(cells[rng.integers(len(cells))])
            b = nav.to_world(cells[rng.integers(len(cells))])
            nav._fields.clear()
            t = time.perf_counter()
            path = nav.path(a, b)
            times.append(time.perf_counter() - t)
            assert path and all(nav.is_walkable(p) for p in _samples(path, 0.02))
    median = float(np.median(times))
    print(f"\npath query (cold) on TwoRoom houses: median {median * 1e3:.2f} ms, "
          f"p95 {np.percentile(times, 95) * 1e3:.2f} ms")
    assert median < 0.005


def test_topdown_map_draws_and_saves(scene: Scene, nav: NavGrid, tmp_path):
    from legent_gym.world.topdown_map import draw_topdown_map, save_topdown_map

    path = nav.path((1.0, 1.0), (7.0, 3.0))
    img = draw_topdown_map(scene, size=400, path=path, navgrid=nav)
    assert img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3
    assert max(img.shape[:2]) <= 400 and img.std() > 10
    out = tmp_path / "maps" / "two_rooms.png"
    save_topdown_map(scene, out, size=300, path=path)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in out.parent.iterdir()] == ["two_rooms.png"]  # no temp file left
