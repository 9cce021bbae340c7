"""The fast paths of a fresh-house reset give exactly what the plain computations give.

Each is checked against the computation it replaces (kept here as the reference) or
against the public result it must reproduce: the generator's navigation grid against
``NavGrid.from_scene``, a renderer that took over a closed renderer's GL resources against
one that made its own, OpenCV's region labels against SciPy's, the path graph against
SciPy's own construction from an edge list, the floor-plan growth against its numpy form.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import ndimage
from scipy.sparse import csr_matrix

from legent_gym.world import render
from legent_gym.world.builder import build_world
from legent_gym.world.generation import generate_house, generate_house_with_grid
from legent_gym.world.generation.floorplan import corner_count
from legent_gym.world.navigation import NavGrid, Raster, label_regions
from legent_gym.world.render import FreeCamera, Renderer


def _same_grid(a: NavGrid, b: NavGrid) -> None:
    assert (a.origin, a.resolution, a.agent_radius, a.shape) == (b.origin, b.resolution, b.agent_radius, b.shape)
    for name in ("floor", "walls", "obstacles", "free", "walkable", "labels"):
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype and np.array_equal(x, y), name
    assert list(a.footprints) == list(b.footprints)
    assert all(a.footprints[k].tobytes() == b.footprints[k].tobytes() for k in a.footprints)
    assert a.scene is b.scene or a.scene == b.scene


@pytest.mark.parametrize("preset", ["OneRoom", "TwoRoom", "FourRoom", "Apartment"])
def test_generator_grid_is_the_scenes_grid(preset):
    for seed in range(4):
        scene, grid = generate_house_with_grid(seed, preset)
        assert scene.to_json() == generate_house(seed, preset).to_json()
        reference = NavGrid.from_scene(scene)
        _same_grid(grid, reference)
        for obj in scene.objects[:6]:
            assert grid.standing_point(obj.id, 1.0, scene.agent.position) == \
                reference.standing_point(obj.id, 1.0, scene.agent.position)
        assert grid.path(scene.agent.position, scene.user.position) == \
            reference.path(scene.agent.position, scene.user.position)


@pytest.mark.parametrize("openness", [0.0, 0.5, 0.7])
def test_generator_grid_follows_door_openness(openness):
    scene, grid = generate_house_with_grid(3, "FourRoom", door_openness=openness)
    _same_grid(grid, NavGrid.from_scene(scene))


def test_for_scene_recomputes_footprints_of_changed_objects():
    scene, grid = generate_house_with_grid(5, "TwoRoom")
    small = next(o for o in scene.objects if o.on is not None)
    moved = scene.model_copy(deep=True)
    moved.objects[small.id].position = (small.position[0] + 0.01, small.position[1], small.position[2])
    _same_grid(grid.for_scene(moved), NavGrid.from_scene(moved))


def _frames(world, size: int, profile: str) -> list[np.ndarray]:
    r = Renderer(world, size, size, profile)
    out = []
    for camera in ("agent", "user", "topdown", FreeCamera((1.0, 1.0, 0.5))):
        out += [r.rgb(camera), r.depth(camera), r.segmentation(camera)]
    r.close()
    return out


@pytest.mark.parametrize("profile", ["fast", "pretty"])
def test_renderer_taking_over_gl_resources_draws_the_same(profile):
    worlds = [build_world(generate_house(seed, preset))
              for seed, preset in [(1, "FourRoom"), (2, "OneRoom"), (4, "Apartment"), (5, "TwoRoom")]]
    fresh = []
    for world in worlds:
        render.free_spare()  # each renderer makes its own context and scene
        fresh.append(_frames(world, 48, profile))
    render.free_spare()
    # Each renderer now takes over the one closed before it (smaller and larger houses
    # alternate, so some take-overs must make a new context).
    reused = [_frames(world, 48, profile) for world in worlds + worlds[::-1]]
    for frames, expected in zip(reused, fresh + fresh[::-1]):
        assert all(np.array_equal(a, b) for a, b in zip(frames, expected))


def test_region_labels_match_scipy():
    rng = np.random.default_rng(0)
    for trial in range(2000):
        h, w = (int(v) for v in rng.integers(1, 50, size=2))
        mask = rng.random((h, w)) < rng.uniform(0.1, 0.95)
        if trial % 3 == 0 and mask.any():
            mask = ndimage.binary_opening(mask)
        labels, n = label_regions(mask)
        expected, m = ndimage.label(mask)
        assert n == m and labels.dtype == expected.dtype and np.array_equal(labels, expected)


def _reference_graph(walk: np.ndarray, res: float) -> csr_matrix:
    """The path graph from its edge list, as SciPy assembles it."""
    h, w = walk.shape
    index = np.full(walk.shape, -1, dtype=np.int64)
    index[walk] = np.arange(int(walk.sum()))
    rows, cols, weights = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        a_rows, b_rows = slice(0, h - dr), slice(dr, h)
        a_cols, b_cols = slice(max(0, -dc), w - max(0, dc)), slice(max(0, dc), w + min(0, dc))
        ok = walk[a_rows, a_cols] & walk[b_rows, b_cols]
        if dr and dc:
            ok &= walk[b_rows, a_cols] & walk[a_rows, b_cols]
        rows.append(index[a_rows, a_cols][ok])
        cols.append(index[b_rows, b_cols][ok])
        weights.append(np.full(int(ok.sum()), res * (math.sqrt(2.0) if dr and dc else 1.0)))
    r, c, wt = np.concatenate(rows), np.concatenate(cols), np.concatenate(weights)
    n = int(walk.sum())
    return csr_matrix((np.concatenate([wt, wt]), (np.concatenate([r, c]), np.concatenate([c, r]))), shape=(n, n))


def test_path_graph_matches_scipys_assembly():
    rng = np.random.default_rng(1)
    for _ in range(200):
        h, w = (int(v) for v in rng.integers(1, 40, size=2))
        walk = rng.random((h, w)) < rng.uniform(0.2, 1.0)
        grid = NavGrid((0.0, 0.0), 0.05, walk, np.zeros_like(walk), np.zeros_like(walk), 0.0)
        graph = grid._path_graph()[0]
        expected = _reference_graph(walk, 0.05)
        for name in ("indptr", "indices", "data"):
            a, b = getattr(graph, name), getattr(expected, name)
            assert a.dtype == b.dtype and np.array_equal(a, b), name


def test_axis_aligned_rectangles_fill_like_the_general_test():
    rng = np.random.default_rng(2)
    raster = Raster((-1.0, -1.0), 0.05, (60, 70))
    for _ in range(500):
        u = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]][int(rng.integers(4))])
        centre = rng.uniform(-1.2, 2.6, size=2).round(int(rng.integers(1, 4)))
        along = tuple(sorted(rng.uniform(-1.0, 1.5, size=2).round(2)))
        across = tuple(sorted(rng.uniform(-1.0, 1.5, size=2).round(2)))
        mask = np.zeros(raster.shape, dtype=bool)
        raster.fill_oriented_rect(mask, centre, u, along, across)
        # The general test on every cell.
        xs = raster.x0 + (np.arange(raster.shape[1]) + 0.5) * raster.res
        ys = raster.y0 + (np.arange(raster.shape[0]) + 0.5) * raster.res
        dx, dy = xs[None, :] - centre[0], ys[:, None] - centre[1]
        pu, pv = dx * u[0] + dy * u[1], dx * -u[1] + dy * u[0]
        eps = 1e-9
        expected = ((pu >= along[0] - eps) & (pu <= along[1] + eps)
                    & (pv >= across[0] - eps) & (pv <= across[1] + eps))
        assert np.array_equal(mask, expected)


def _reference_corner_count(mask: np.ndarray) -> int:
    p = np.pad(mask.astype(np.int8), 1)
    a, b, c, d = p[:-1, :-1], p[:-1, 1:], p[1:, :-1], p[1:, 1:]
    s = a + b + c + d
    if ((s == 2) & (a == d)).any():
        return 99
    return int(((s == 1) | (s == 3)).sum())


def test_corner_count_matches_the_array_form():
    rng = np.random.default_rng(3)
    for _ in range(3000):
        mask = rng.random((int(rng.integers(1, 7)), int(rng.integers(1, 7)))) < 0.6
        if mask.any():
            assert corner_count(mask) == _reference_corner_count(mask)
