"""The navigation grid's shortcuts give what the full computations give, to the bit:
``NavGrid.with_obstacles`` (a person standing added to a grid) against a grid made from
scratch, and ``reach_cells(rank=...)`` against sorting every cell in sight."""

import numpy as np
import pytest

from legent_gym.world.generation import generate_house_with_grid
from legent_gym.world.navigation import NavGrid


def _disc(nav: NavGrid, xy, radius: float) -> np.ndarray:
    rows, cols = np.ogrid[:nav.shape[0], :nav.shape[1]]
    cx = nav.origin[0] + (cols + 0.5) * nav.resolution
    cy = nav.origin[1] + (rows + 0.5) * nav.resolution
    return np.hypot(cx - xy[0], cy - xy[1]) <= radius


@pytest.mark.parametrize("layout,seed,margin", [("OneRoom", 1, 0.06), ("TwoRoom", 2, 0.06), ("TwoRoom", 3, 0.0)])
def test_with_obstacles_is_the_grid_made_from_scratch(layout, seed, margin):
    _, nav = generate_house_with_grid(seed, layout)
    base = NavGrid(nav.origin, nav.resolution, nav.floor, nav.walls, nav.obstacles, nav.agent_radius + margin)
    rng = np.random.default_rng(seed)
    cells = np.argwhere(nav.walkable)
    for _ in range(4):
        person = np.asarray(nav.to_world(cells[rng.integers(len(cells))])) + rng.uniform(-0.02, 0.02, 2)
        extra = _disc(nav, person, 0.22)
        full = NavGrid(nav.origin, nav.resolution, nav.floor, nav.walls, nav.obstacles | extra, base.agent_radius)
        quick = base.with_obstacles(extra)
        assert (quick.walkable != base.walkable).any()  # the person does block cells
        np.testing.assert_array_equal(quick.walkable, full.walkable)
        np.testing.assert_array_equal(quick.labels, full.labels)
        for _ in range(3):
            a, b = (nav.to_world(cells[rng.integers(len(cells))]) for _ in range(2))
            np.testing.assert_array_equal(quick.distance_field(a), full.distance_field(a))
            assert quick.path(a, b) == full.path(a, b)


def test_with_obstacles_of_nothing_new_shares_the_grid():
    _, nav = generate_house_with_grid(0, "OneRoom")
    same = nav.with_obstacles(~nav.free)  # only cells that are blocked already
    np.testing.assert_array_equal(same.walkable, nav.walkable)
    a, b = (nav.to_world(c) for c in np.argwhere(nav.walkable)[[0, -1]])
    assert same.path(a, b) == nav.path(a, b)


def test_reach_cells_rank_is_the_first_of_the_sorted_cells():
    _, nav = generate_house_with_grid(2, "TwoRoom")
    rng = np.random.default_rng(0)
    cells = np.argwhere(nav.walkable)
    for _ in range(10):
        start = nav.to_world(cells[rng.integers(len(cells))])
        target = np.asarray(nav.to_world(cells[rng.integers(len(cells))]))
        corners = np.repeat(target[None, :], 4, axis=0)
        component = nav.component(start)
        field = nav.distance_field(start)
        every, _ = nav.reach_cells(corners, 1.0, component)
        first, _ = nav.reach_cells(corners, 1.0, component, rank=lambda f=field: f)
        dist = field[every[:, 0], every[:, 1]]
        order = np.argsort(dist, kind="stable")
        order = order[np.isfinite(dist[order])]
        if len(order):
            np.testing.assert_array_equal(first, every[order[:1]])
        else:
            assert len(first) == 0
