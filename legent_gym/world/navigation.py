"""Walkable floor and shortest paths over a scene, computed from the scene data alone.

:class:`NavGrid` rasterises a :class:`~legent_gym.world.scene.Scene` into an occupancy grid
(no physics, no rendering): room floors are free, walls are blocked except where a door is
passable, floor furniture blocks with its footprint (asset bounds, scaled and rotated by
yaw), small objects are ignored. Obstacles are inflated by the agent radius with a
Euclidean distance transform, so a cell is *walkable* when a disc of that radius centred
on it touches nothing.

Queries: :meth:`NavGrid.path` (grid Dijkstra from the goal, cached per goal, then a
line-of-sight string-pull so a path has few corners), :meth:`NavGrid.distance` (geodesic
metres), :meth:`NavGrid.distance_field`, :meth:`NavGrid.is_walkable`,
:meth:`NavGrid.nearest_walkable`, :meth:`NavGrid.reachable` and
:meth:`NavGrid.standing_point` (where to stand to reach an object).

Doors: a door is passable when ``openness > 0.5`` or it has no leaf (an archway); a
passable door's leaf is taken to stand fully open (perpendicular to the wall at its hinge,
on its swing side) and blocks as a thin slab; a closed door blocks like the wall.

Grid convention: cell ``(row, col)`` covers ``x in [x0 + col*res, x0 + (col+1)*res)`` and
``y in [y0 + row*res, ...)``; rows grow with y.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Sequence

import numpy as np
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from legent_gym.world.geometry import (
    axis_aligned_closest,
    closest_points_on_rect,
    door_leaf_open_segment,
    door_passable,
    inside_polygon,
    is_floor_furniture,
    object_footprint,
    wall_frame,
    wall_solid_spans,
)
from legent_gym.world.scene import Door, Scene

DEFAULT_AGENT_RADIUS = 0.25
DEFAULT_RESOLUTION = 0.05
#: Thickness of an open door leaf, metres (for the occupancy only).
LEAF_THICKNESS = 0.04

XY = tuple[float, float]
#: A cell's 8 neighbours (row, column offsets) in raster order.
_NEIGHBOURS = ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1))


# ---------------------------------------------------------------------------------------
# Rasterisation helpers (cell centres inside a shape)


def leaf_half_thickness(resolution: float) -> float:
    """Half thickness used to rasterise an open leaf: at least half a cell, so that a thin
    slab between cell centres is not lost."""
    return max(LEAF_THICKNESS / 2, 0.5 * resolution)


class Raster:
    """Maps world coordinates to a grid and fills shapes into boolean masks."""

    def __init__(self, origin: XY, resolution: float, shape: tuple[int, int]):
        self.x0, self.y0 = float(origin[0]), float(origin[1])
        self.res = float(resolution)
        self.shape = shape
        self._centres: tuple[np.ndarray, np.ndarray] | None = None

    def window(self, xmin: float, ymin: float, xmax: float, ymax: float):
        """Index ranges and cell-centre coordinates covering a world box (clipped); the
        coordinates are read-only views."""
        h, w = self.shape
        c0 = max(0, int(math.floor((xmin - self.x0) / self.res)))
        c1 = min(w, int(math.ceil((xmax - self.x0) / self.res)) + 1)
        r0 = max(0, int(math.floor((ymin - self.y0) / self.res)))
        r1 = min(h, int(math.ceil((ymax - self.y0) / self.res)) + 1)
        if c0 >= c1 or r0 >= r1:
            return None
        if self._centres is None:  # every column's and row's centre, computed once
            xs = self.x0 + (np.arange(w) + 0.5) * self.res
            ys = self.y0 + (np.arange(h) + 0.5) * self.res
            xs.flags.writeable = ys.flags.writeable = False
            self._centres = (xs[None, :], ys[:, None])
        xs, ys = self._centres
        return (slice(r0, r1), slice(c0, c1)), xs[:, c0:c1], ys[r0:r1]

    def fill_polygon(self, mask: np.ndarray, polygon: np.ndarray) -> None:
        """Fill cells whose centre lies inside the polygon (even-odd rule)."""
        poly = np.asarray(polygon, dtype=np.float64)
        win = self.window(*poly.min(axis=0), *poly.max(axis=0))
        if win is None:
            return
        sl, xs, ys = win
        mask[sl] |= inside_polygon(xs, ys, poly)

    def fill_oriented_rect(self, mask: np.ndarray, centre: np.ndarray, u: np.ndarray,
                           along: tuple[float, float], across: tuple[float, float]) -> None:
        """Fill cells whose centre p has ``(p - centre) . u`` in ``along`` and
        ``(p - centre) . perp(u)`` in ``across``."""
        ux, uy, cx, cy = float(u[0]), float(u[1]), float(centre[0]), float(centre[1])
        vx, vy = -uy, ux
        # The corners' box, in scalars (the arithmetic of centre + u * a + v * b per axis).
        corner_x = [cx + ux * a + vx * b for a in along for b in across]
        corner_y = [cy + uy * a + vy * b for a in along for b in across]
        win = self.window(min(corner_x), min(corner_y), max(corner_x), max(corner_y))
        if win is None:
            return
        sl, xs, ys = win
        dx, dy = xs - cx, ys - cy
        eps = 1e-9
        if ux == 0.0 or uy == 0.0:
            # Along the axes, each projection is one term plus an exact zero (which can
            # only flip a zero's sign): the test splits into a column test and a row test.
            pu, pv = (dx * ux, dy * vy) if uy == 0.0 else (dy * uy, dx * vx)
            in_along = (pu >= along[0] - eps) & (pu <= along[1] + eps)
            mask[sl] |= in_along & ((pv >= across[0] - eps) & (pv <= across[1] + eps))
            return
        pu = dx * ux + dy * uy
        pv = dx * vx + dy * vy
        mask[sl] |= ((pu >= along[0] - eps) & (pu <= along[1] + eps)
                     & (pv >= across[0] - eps) & (pv <= across[1] + eps))

    def fill_corners(self, mask: np.ndarray, corners: np.ndarray) -> None:
        """Fill a rectangle given by its 4 corners (any orientation)."""
        c = np.asarray(corners, dtype=np.float64)
        e0 = c[1] - c[0]
        length0 = float(np.hypot(*e0))
        if length0 <= 0:
            return
        u = e0 / length0
        v = np.array([-u[1], u[0]])
        width = float(np.dot(c[3] - c[0], v))
        across = (0.0, width) if width >= 0 else (width, 0.0)
        self.fill_oriented_rect(mask, c[0], u, (0.0, length0), across)


def walkable_from_free(free: np.ndarray, radius: float, resolution: float) -> np.ndarray:
    """Cells of ``free`` whose clearance to any blocked cell is at least ``radius``.

    The distance transform measures centre to centre; half a cell is added because the
    obstacle's edge may lie anywhere in the blocked cell.
    """
    if radius <= 0:
        return free.copy()
    return clearance_at_least(free, radius + 0.5 * resolution, resolution)


def least_square_distance(distance: float, resolution: float) -> int:
    """The least integer ``n`` (a squared distance between cell centres, in cells) with
    ``sqrt(n) * resolution >= distance``, in the float arithmetic the distance transform's
    users apply."""
    n = max(int((distance / resolution) ** 2) - 2, 0) if distance > 0 else 0
    while n > 0 and math.sqrt(n - 1) * resolution >= distance:
        n -= 1
    while math.sqrt(n) * resolution < distance:
        n += 1
    return n


def clearance_at_least(free: np.ndarray, distance: float, resolution: float) -> np.ndarray:
    """``ndimage.distance_transform_edt(free) * resolution >= distance``, the same cells,
    about three times faster.

    Squared distances between cell centres are integers, so the test is ``d2 >= n`` for the
    least integer ``n`` that passes it (found with the same float arithmetic). OpenCV's exact
    Euclidean transform gives ``sqrt(d2)`` in float32, accurate enough to tell ``d2`` from
    ``d2 - 1``; SciPy's is kept for a grid with no blocked cell (where the two differ).
    """
    if free.all():
        return ndimage.distance_transform_edt(free) * resolution >= distance
    n = least_square_distance(distance, resolution)
    if n == 0:
        return np.ones(free.shape, dtype=bool)
    import cv2  # a core dependency, imported when first needed (~0.2 s)

    dist = cv2.distanceTransform(np.ascontiguousarray(free, dtype=np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    # dist**2 is within 0.02 of the integer d2 (float32 error), so halfway is a safe cut.
    return dist >= np.float32(math.sqrt(n - 0.5))


def label_regions(mask: np.ndarray) -> tuple[np.ndarray, int]:
    """``ndimage.label(mask)``: 4-connected regions numbered 1.. in raster order of their
    first cell (0 elsewhere), as int32, and their count; by OpenCV's labelling, which
    numbers them the same way at half the cost."""
    if mask.size == 0:
        return ndimage.label(mask)
    import cv2  # a core dependency, imported when first needed (~0.2 s)

    n, labels = cv2.connectedComponents(np.ascontiguousarray(mask, dtype=np.uint8), connectivity=4,
                                        ltype=cv2.CV_32S)
    return labels, n - 1


# ---------------------------------------------------------------------------------------


#: The most can_reach answers a grid keeps (a generated house asks about a hundred).
REACH_MEMO_SIZE = 4096


class NavGrid:
    """Occupancy grid of walkable floor, with shortest paths and reach queries.

    Build it with :meth:`from_scene`. Everything is in world metres; points are ``(x, y)``.
    """

    def __init__(self, origin: XY, resolution: float, floor: np.ndarray, walls: np.ndarray,
                 obstacles: np.ndarray, agent_radius: float, *, scene: Scene | None = None,
                 footprints: dict[int, np.ndarray] | None = None, walkable: np.ndarray | None = None):
        self.origin = (float(origin[0]), float(origin[1]))
        self.resolution = float(resolution)
        self.agent_radius = float(agent_radius)
        self.floor = floor
        #: Walls and closed doors (what blocks line of sight at floor level).
        self.walls = walls
        #: Furniture footprints and open door leaves.
        self.obstacles = obstacles
        self.free = floor & ~walls & ~obstacles
        # ``walkable``: what walkable_from_free gives, when the caller has it (with_obstacles).
        self.walkable = walkable_from_free(self.free, self.agent_radius, self.resolution) if walkable is None \
            else walkable
        self.scene = scene
        self.footprints = footprints or {}
        self.raster = Raster(self.origin, self.resolution, self.free.shape)
        self._labels: np.ndarray | None = None
        self._nearest: np.ndarray | None = None
        self._graph: csr_matrix | None = None
        self._index: np.ndarray | None = None
        self._cells: np.ndarray | None = None
        #: The cells that are the path graph's nodes, in raster order (the walkable cells;
        #: a grid made by :meth:`with_obstacles` keeps its source's, some left unlinked).
        self._numbered = self.walkable
        self._fields: OrderedDict[int, tuple[np.ndarray, np.ndarray]] = OrderedDict()
        self._open: np.ndarray | None = None
        self._component_masks: dict[int, np.ndarray] = {}
        self._padded_masks: dict[str, np.ndarray] = {}
        #: can_reach's answers by (corners, reach, component): the house generator asks of a
        #: receptacle's rectangle while placing on it, and its check of the house again.
        self._reach_memo: dict[tuple[bytes, float, int | None], bool] = {}
        self.cache_size = 32

    # -- construction -------------------------------------------------------------------
    @classmethod
    def from_scene(cls, scene: Scene, agent_radius: float = DEFAULT_AGENT_RADIUS,
                   resolution: float = DEFAULT_RESOLUTION, *, ignore_objects: bool = False,
                   margin: float = 0.5) -> NavGrid:
        """Rasterise ``scene``: floors, walls (with passable door openings), open door
        leaves and floor furniture footprints; inflate obstacles by ``agent_radius``."""
        (xmin, ymin), (xmax, ymax) = scene.bounds()
        origin = (xmin - margin, ymin - margin)
        shape = (int(math.ceil((ymax - ymin + 2 * margin) / resolution)),
                 int(math.ceil((xmax - xmin + 2 * margin) / resolution)))
        raster = Raster(origin, resolution, shape)
        floor = np.zeros(shape, dtype=bool)
        for room in scene.rooms:
            raster.fill_polygon(floor, np.asarray(room.polygon))
        walls = np.zeros(shape, dtype=bool)
        obstacles = np.zeros(shape, dtype=bool)
        _fill_walls(raster, walls, obstacles, scene)
        footprints = {}
        for obj in scene.objects:
            fp = object_footprint(scene, obj)
            if fp is None:
                continue
            footprints[obj.id] = fp
            if is_floor_furniture(obj) and not ignore_objects:
                raster.fill_corners(obstacles, fp)
        return cls(origin, resolution, floor, walls, obstacles, agent_radius, scene=scene,
                   footprints=footprints)

    def for_scene(self, scene: Scene) -> NavGrid:
        """``NavGrid.from_scene(scene)`` with this grid's radius and resolution, for a scene
        whose rooms, walls, door openings and floor furniture are those of the scene this
        grid was made from (the caller vouches for it; the house generator hands its grid
        of the bare house over to the furnished one so): objects that block nothing (those
        resting on others) may differ. The cells and what was worked out from them (regions,
        the path graph, ...) are shared; only footprints of objects new to the grid are
        computed."""
        state = dict(vars(self))
        state.update(scene=scene, footprints=self.footprints_for(scene),
                     # Caches of the same cells, copied so that the two grids' caches grow apart.
                     _fields=OrderedDict(self._fields), _component_masks=dict(self._component_masks),
                     _padded_masks=dict(self._padded_masks), _reach_memo=dict(self._reach_memo))
        grid = type(self).__new__(type(self))
        vars(grid).update(state)
        return grid

    def footprints_for(self, scene: Scene) -> dict[int, np.ndarray]:
        """Footprint corners of ``scene``'s objects (those of known size), what
        ``object_footprint`` gives: the grid's own for objects it was made with (equal
        objects, the same imported assets), computed for the others."""
        before = {}
        if self.scene is not None and (self.scene is scene or self.scene.assets == scene.assets):
            before = {o.id: o for o in self.scene.objects}
        footprints = {}
        for obj in scene.objects:
            old = before.get(obj.id)
            fp = self.footprints.get(obj.id) if old is obj or old == obj else None
            if fp is None:
                fp = object_footprint(scene, obj)
            if fp is not None:
                footprints[obj.id] = fp
        return footprints

    def with_obstacles(self, extra: np.ndarray) -> NavGrid:
        """``NavGrid(origin, resolution, floor, walls, obstacles | extra, agent_radius)`` (the
        same cells, components, distances and paths), for less when ``extra`` (a mask) blocks
        a few cells, such as a person standing: the walkable cells are this grid's less those
        within the agent's clearance of a newly blocked cell (squared distances between cells
        are integers: the test :func:`clearance_at_least` makes), and the path graph is this
        grid's with the edges those cells break taken out. Its nodes keep this grid's numbers
        (the cells that lost theirs keep them, unlinked), which changes no search: Dijkstra's
        heap orders nodes by distance alone and a node's edges keep their order."""
        extra = np.asarray(extra, dtype=bool)
        obstacles = self.obstacles | extra
        newly = extra & self.free
        rows, cols = np.nonzero(newly)
        h, w = self.shape
        walkable: np.ndarray | None = None
        lost = None  # (first row, first column, the cells that are no longer walkable there)
        if len(rows) == 0:
            walkable = self.walkable
        elif self.agent_radius > 0 and not self.free.all():  # else walkable_from_free's other cases
            n = least_square_distance(self.agent_radius + 0.5 * self.resolution, self.resolution)
            m = math.isqrt(max(n - 1, 0))
            r0, r1 = max(int(rows.min()) - m, 0), min(int(rows.max()) + m + 1, h)
            c0, c1 = max(int(cols.min()) - m, 0), min(int(cols.max()) + m + 1, w)
            if (r1 - r0) * (c1 - c0) * len(rows) <= 1 << 21:  # else a transform of the grid is cheaper
                wr, wc = np.mgrid[r0:r1, c0:c1]
                d2 = (wr.reshape(-1, 1) - rows[None, :]) ** 2 + (wc.reshape(-1, 1) - cols[None, :]) ** 2
                near = ~(d2 >= n).all(axis=1).reshape(r1 - r0, c1 - c0)
                walkable = self.walkable.copy()
                walkable[r0:r1, c0:c1] &= ~near
                lost = (r0, c0, near & self.walkable[r0:r1, c0:c1])
        grid = NavGrid(self.origin, self.resolution, self.floor, self.walls, obstacles, self.agent_radius,
                       scene=self.scene, footprints=self.footprints, walkable=walkable)
        if walkable is not None:
            self._unlink(grid, lost)
        return grid

    def _unlink(self, grid: NavGrid, lost: tuple[int, int, np.ndarray] | None) -> None:
        """Give ``grid`` (this grid less the ``lost`` walkable cells) this grid's path graph
        less the edges of those cells and the diagonals that would cut their corners."""
        graph, index, cells = self._path_graph()
        if lost is None or not lost[2].any():
            grid._graph, grid._index, grid._cells, grid._numbered = graph, index, cells, self._numbered
            return
        walk = grid.walkable
        h, w = walk.shape
        rows, cols = np.nonzero(lost[2])
        rows += lost[0]
        cols += lost[1]
        # The only rows that change: nodes within one cell of a removed one (a box of them).
        r0, r1 = max(int(rows.min()) - 1, 0), min(int(rows.max()) + 2, h)
        c0, c1 = max(int(cols.min()) - 1, 0), min(int(cols.max()) + 2, w)
        near = index[r0:r1, c0:c1]
        nodes = near[near >= 0]
        indptr = graph.indptr
        starts, counts = indptr[nodes], indptr[nodes + 1] - indptr[nodes]
        total = int(counts.sum())
        first = np.repeat(starts - np.concatenate([[0], np.cumsum(counts)[:-1]]), counts)
        entries = first + np.arange(total)
        src = cells[np.repeat(nodes, counts)]
        dst = cells[graph.indices[entries]]
        sr, sc, tr, tc = src[:, 0], src[:, 1], dst[:, 0], dst[:, 1]
        ok = walk[sr, sc] & walk[tr, tc] & walk[tr, sc] & walk[sr, tc]  # diagonals: both corners
        # The rows of these nodes make one run of entries (the nodes are in raster order):
        # only that run is filtered; the entries before and after it are copied as they are.
        a, b = int(indptr[nodes[0]]), int(indptr[nodes[-1] + 1])
        keep = np.ones(b - a, dtype=bool)
        keep[entries[~ok] - a] = False
        dropped = np.zeros(len(indptr), dtype=indptr.dtype)
        np.cumsum(np.bincount(np.repeat(nodes, counts)[~ok] - nodes[0], minlength=nodes[-1] - nodes[0] + 1),
                  out=dropped[nodes[0] + 1:nodes[-1] + 2])
        dropped[nodes[-1] + 2:] = dropped[nodes[-1] + 1]
        data, indices = graph.data, graph.indices
        grid._graph = csr_matrix((np.concatenate([data[:a], data[a:b][keep], data[b:]]),
                                  np.concatenate([indices[:a], indices[a:b][keep], indices[b:]]), indptr - dropped),
                                 shape=graph.shape)
        unlinked = index.copy()
        unlinked[rows, cols] = -1
        grid._index, grid._cells, grid._numbered = unlinked, cells, self._numbered

    # -- coordinates --------------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int]:
        return self.free.shape

    def to_cell(self, xy: Sequence[float]) -> tuple[int, int]:
        """(row, col) of the cell holding ``xy`` (may lie outside the grid)."""
        return (int(math.floor((xy[1] - self.origin[1]) / self.resolution)),
                int(math.floor((xy[0] - self.origin[0]) / self.resolution)))

    def to_world(self, cell: Sequence[int]) -> XY:
        """Centre of cell ``(row, col)``."""
        return (self.origin[0] + (cell[1] + 0.5) * self.resolution,
                self.origin[1] + (cell[0] + 0.5) * self.resolution)

    def _inside(self, cell: tuple[int, int]) -> bool:
        return 0 <= cell[0] < self.shape[0] and 0 <= cell[1] < self.shape[1]

    def _clamp(self, cell: tuple[int, int]) -> tuple[int, int]:
        return (min(max(cell[0], 0), self.shape[0] - 1), min(max(cell[1], 0), self.shape[1] - 1))

    # -- simple queries -----------------------------------------------------------------
    def is_walkable(self, xy: Sequence[float]) -> bool:
        """Whether the agent (a disc of ``agent_radius``) can stand at ``xy``."""
        cell = self.to_cell(xy)
        return self._inside(cell) and bool(self.walkable[cell])

    def _snap(self, xy: Sequence[float]) -> tuple[int, int] | None:
        """The walkable cell nearest to ``xy`` (None when nothing is walkable)."""
        cell = self._clamp(self.to_cell(xy))
        if self.walkable[cell]:
            return cell
        nearest = self._nearest_table()
        if nearest is None:
            return None
        return int(nearest[0][cell]), int(nearest[1][cell])

    def _nearest_table(self) -> np.ndarray | None:
        """For every cell, the indices of the nearest walkable cell (computed once)."""
        if self._nearest is None and self.walkable.any():
            _, self._nearest = ndimage.distance_transform_edt(~self.walkable, return_indices=True)
        return self._nearest

    def nearest_walkable_cell(self, xy: Sequence[float]) -> tuple[int, int] | None:
        """The cell of :meth:`nearest_walkable` (None when nothing is walkable)."""
        return self._snap(xy)

    def nearest_walkable(self, xy: Sequence[float]) -> XY | None:
        """``xy`` itself when walkable, else the centre of the nearest walkable cell."""
        if self.is_walkable(xy):
            return (float(xy[0]), float(xy[1]))
        cell = self._snap(xy)
        return None if cell is None else self.to_world(cell)

    @property
    def labels(self) -> np.ndarray:
        """Connected components of walkable cells (0 = not walkable)."""
        if self._labels is None:
            self._labels, _ = label_regions(self.walkable)
        return self._labels

    def component(self, xy: Sequence[float]) -> int:
        """Label of the component of the walkable cell nearest to ``xy`` (0: none)."""
        cell = self._snap(xy)
        return 0 if cell is None else int(self.labels[cell])

    def reachable(self, a: Sequence[float], b: Sequence[float]) -> bool:
        """Whether a path joins ``a`` and ``b`` (each snapped to its nearest walkable cell)."""
        ca, cb = self.component(a), self.component(b)
        return ca != 0 and ca == cb

    # -- shortest paths -----------------------------------------------------------------
    def _build_graph(self) -> None:
        """8-connected graph over walkable cells; a diagonal step needs both of the cells it
        passes between to be walkable (no cutting corners).

        Nodes are the walkable cells in raster order, so a cell's neighbours, taken in
        raster order, have ascending node numbers: the rows of the CSR matrix are written
        directly, sorted, as SciPy would sort them from a list of edges."""
        walk = self.walkable
        h, w = walk.shape
        n = int(np.count_nonzero(walk))
        # SciPy's choice of index type: 32 bits when every index and count fits (a node has
        # at most 8 edges).
        dtype = np.int32 if 8 * n <= np.iinfo(np.int32).max else np.int64
        padded = np.full((h + 2, w + 2), -1, dtype=dtype)
        index = padded[1:-1, 1:-1]
        index[walk] = np.arange(n, dtype=dtype)
        cells = np.argwhere(walk)
        # Each cell's neighbours (node-major, directions in raster order: the CSR rows in
        # order) through flat offsets into the padded grid (-1: none), in one gather.
        at = (cells[:, 0] + 1) * (w + 2) + (cells[:, 1] + 1)
        offsets = np.array([dr * (w + 2) + dc for dr, dc in _NEIGHBOURS])
        neighbours = padded.ravel().take(at[:, None] + offsets[None, :])
        for k, (dr, dc) in enumerate(_NEIGHBOURS):
            if dr and dc:  # no cutting corners: both cells it passes between are walkable
                blocked = (neighbours[:, _NEIGHBOURS.index((dr, 0))] < 0) | (neighbours[:, _NEIGHBOURS.index((0, dc))] < 0)
                neighbours[blocked, k] = -1
        res = self.resolution
        steps = np.array([res * math.sqrt(2.0) if dr and dc else res * 1.0 for dr, dc in _NEIGHBOURS])
        edge = neighbours >= 0
        indptr = np.zeros(n + 1, dtype=dtype)
        np.cumsum(np.count_nonzero(edge, axis=1), out=indptr[1:])
        weights = np.broadcast_to(steps, edge.shape)[edge]
        self._graph = csr_matrix((weights, neighbours[edge], indptr), shape=(n, n))
        self._index = index
        self._cells = cells

    def _path_graph(self) -> tuple[csr_matrix, np.ndarray, np.ndarray]:
        """(the path graph, each cell's graph node or -1, each node's cell), built on first use."""
        if self._graph is None:
            self._build_graph()
        graph, index, cells = self._graph, self._index, self._cells
        if graph is None or index is None or cells is None:
            raise RuntimeError("the path graph was not built")
        return graph, index, cells

    def precompute(self) -> NavGrid:
        """Build the path graph, components and snapping table now (else on first use)."""
        if self._graph is None:
            self._build_graph()
        _ = self.labels
        self._nearest_table()
        return self

    def _field(self, cell: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """(distances, predecessors) over graph nodes from ``cell``, cached (LRU)."""
        graph, index, _ = self._path_graph()
        node = int(index[cell])
        hit = self._fields.get(node)
        if hit is not None:
            self._fields.move_to_end(node)
            return hit
        dist, pred = dijkstra(graph, directed=True, indices=node, return_predecessors=True)
        self._fields[node] = (dist, pred)
        if len(self._fields) > self.cache_size:
            self._fields.popitem(last=False)
        return dist, pred

    def distance_field(self, goal: Sequence[float]) -> np.ndarray:
        """Grid geodesic distance (metres) from every cell to ``goal``; ``inf`` where not
        walkable or not connected. Cached per goal cell, so it is cheap to ask again."""
        out = np.full(self.shape, np.inf)
        cell = self._snap(goal)
        if cell is None:
            return out
        dist, _ = self._field(cell)
        out[self._numbered] = dist
        return out

    def path(self, start: Sequence[float], goal: Sequence[float]) -> list[XY]:
        """Shortest walkable path from ``start`` to ``goal`` as a list of corner points,
        starting at ``start`` and ending at ``goal`` (each replaced by its nearest walkable
        point when not walkable). ``[]`` when there is no path."""
        s_cell, g_cell = self._snap(start), self._snap(goal)
        if s_cell is None or g_cell is None:
            return []
        if self.labels[s_cell] != self.labels[g_cell]:
            return []
        start_pt = self._endpoint(start, s_cell)
        goal_pt = self._endpoint(goal, g_cell)
        if s_cell == g_cell:
            return [start_pt] if start_pt == goal_pt else [start_pt, goal_pt]
        _, pred = self._field(g_cell)
        _, index, cells = self._path_graph()
        node = int(index[s_cell])
        chain = [node]
        while node >= 0 and pred[node] >= 0:
            node = int(pred[node])
            chain.append(node)
        rc = cells[np.asarray(chain)].astype(np.float64) + 0.5  # continuous (row, col)
        pts = np.column_stack([rc[:, 1], rc[:, 0]])  # (col, row) == grid x, y
        pts[0] = self._grid_xy(start_pt)
        pts[-1] = self._grid_xy(goal_pt)
        keep = self._string_pull(pts)
        return [self._world_xy(pts[i]) for i in keep]

    def distance(self, a: Sequence[float], b: Sequence[float]) -> float:
        """Geodesic distance in metres along :meth:`path` (``inf`` when unreachable)."""
        pts = self.path(a, b)
        if not pts:
            return math.inf
        return float(sum(math.dist(p, q) for p, q in zip(pts, pts[1:])))

    def _endpoint(self, xy: Sequence[float], cell: tuple[int, int]) -> XY:
        if self.to_cell(xy) == cell:
            return (float(xy[0]), float(xy[1]))
        return self.to_world(cell)

    def _grid_xy(self, xy: Sequence[float] | np.ndarray) -> np.ndarray:
        return np.array([(xy[0] - self.origin[0]) / self.resolution, (xy[1] - self.origin[1]) / self.resolution])

    def _world_xy(self, g: np.ndarray) -> XY:
        return (round(self.origin[0] + float(g[0]) * self.resolution, 6),
                round(self.origin[1] + float(g[1]) * self.resolution, 6))

    def _string_pull(self, pts: np.ndarray, max_targets: int = 64) -> list[int]:
        """Indices of the path points kept: from each kept point, jump to the furthest of a
        sample of later points in clear line of sight (checked on the walkable mask)."""
        n = len(pts)
        keep = [0]
        anchor = 0
        while anchor < n - 1:
            step = max(1, (n - 1 - anchor) // max_targets)
            cand = np.arange(anchor + 1, n, step)
            if cand[-1] != n - 1:
                cand = np.append(cand, n - 1)
            visible = self._clear_many(pts[anchor], pts[cand])
            # The next point is always reachable (adjacent cells, no corner cutting).
            k = int(np.nonzero(visible)[0][-1]) if visible.any() else -1
            best = int(cand[k]) if k >= 0 else anchor + 1
            upto = int(cand[k + 1]) if k + 1 < len(cand) else best
            if upto > best + 1:  # refine between the last visible sample and the next one
                between = np.arange(best + 1, upto)
                seen = self._clear_many(pts[anchor], pts[between])
                if seen.any():
                    best = int(between[np.nonzero(seen)[0][-1]])
            keep.append(best)
            anchor = best
        return keep

    def _clear_many(self, a: np.ndarray, targets: np.ndarray) -> np.ndarray:
        """For each target, whether segment a -> target (grid coordinates) passes only
        through walkable cells: every cell it enters is found from its crossings of the
        grid lines (an exact supercover, vectorised over targets)."""
        return _padded_segments_clear(self._padded_mask("walkable"), a, targets)

    # -- line of sight and reach --------------------------------------------------------
    def line_of_sight(self, a: Sequence[float] | np.ndarray, b: Sequence[float] | np.ndarray, *,
                      through: str = "walls") -> bool:
        """Whether segment a -> b crosses no wall (``through="walls"``) or stays on
        walkable cells (``through="walkable"``)."""
        ga, gb = self._grid_xy(a), self._grid_xy(b)
        if through == "walkable":
            return bool(self._clear_many(ga, gb[None, :])[0])
        return bool(self._wall_free(ga[None, :], gb[None, :])[0])

    def _wall_free(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Segments a[i] -> b[i] (grid coordinates) that cross no wall cell."""
        return _padded_segments_clear(self._padded_mask("open"), a, b)

    def _padded_mask(self, which: str) -> np.ndarray:
        """The walkable (``"walkable"``) or wall-free (``"open"``) mask with a false border,
        for the segment tests (made once)."""
        padded = self._padded_masks.get(which)
        if padded is None:
            padded = self._padded_masks[which] = _padded(self.walkable if which == "walkable" else self._open_mask())
        return padded

    def _open_mask(self) -> np.ndarray:
        """Cells free of walls (and of closed doors)."""
        if self._open is None:
            self._open = ~self.walls
        return self._open

    def footprint(self, object_id: int) -> np.ndarray:
        """World corners (4, 2) of an object's footprint."""
        if object_id not in self.footprints:
            raise KeyError(f"no footprint for object {object_id} (unknown id or asset size)")
        return self.footprints[object_id]

    def can_reach(self, corners: np.ndarray, reach: float = 1.0, component: int | None = None) -> bool:
        """Whether some walkable cell (of ``component``) is within ``reach`` of the
        rectangle ``corners`` with no wall between."""
        c = np.ascontiguousarray(corners, dtype=np.float64)
        key = (c.tobytes(), float(reach), component)
        found = self._reach_memo.get(key)
        if found is None:
            if len(self._reach_memo) >= REACH_MEMO_SIZE:  # objects moved about a kept house ask anew
                self._reach_memo.clear()
            found = self._reach_memo[key] = len(self.reach_cells(c, reach, component, first_only=True)[0]) > 0
        return found

    def reach_cells(self, corners: np.ndarray, reach: float, component: int | None = None, *,
                    first_only: bool = False, rank=None) -> tuple[np.ndarray, np.ndarray]:
        """Walkable cells (N, 2 as row, col) within ``reach`` metres of the rectangle
        ``corners`` and in line of sight of it (no wall between), with their distances;
        sorted nearest first. ``component`` restricts to one connected component;
        ``first_only`` returns just the nearest such cell (faster). ``rank`` (a function
        giving a value per cell of the grid, such as :meth:`distance_field`; called only
        when there are cells within reach) returns just the cell of least finite value (of
        equal values the nearest), the one a stable sort of the cells by value puts first;
        cells are tested for sight in that order, so usually only one is."""
        c = np.asarray(corners, dtype=np.float64)
        lo, hi = c.min(axis=0) - reach, c.max(axis=0) + reach
        win = self.raster.window(lo[0], lo[1], hi[0], hi[1])
        empty = (np.zeros((0, 2), dtype=np.int64), np.zeros(0))
        if win is None:
            return empty
        sl, xs, ys = win
        sub = (self.walkable if component is None else self._component_mask(component))[sl]
        separable = axis_aligned_closest(c, xs[0], ys[:, 0])
        if separable is not None:
            # An axis-aligned footprint (furniture turns by quarter turns): the nearest
            # point's x depends on the column only and its y on the row only.
            nx, ny = separable
            within = np.hypot((nx - xs[0])[None, :], (ny - ys[:, 0])[:, None])
            near = sub & (within <= reach)
            if first_only and rank is None:
                hit = self._nearest_if_in_sight(near, within, nx, ny, xs, ys, sl)
                if hit is not None:
                    return hit
            rr, cc = np.nonzero(near)
            if len(rr) == 0:
                return empty
            px, py, dist = xs[0, cc], ys[rr, 0], within[rr, cc]
            nearest = np.column_stack([nx[cc], ny[rr]])
            order = np.argsort(dist, kind="stable")
        else:
            rr, cc = np.nonzero(sub)
            if len(rr) == 0:
                return empty
            px, py = xs[0, cc], ys[rr, 0]
            nearest = closest_points_on_rect(c, np.column_stack([px, py]))
            dist = np.hypot(nearest[:, 0] - px, nearest[:, 1] - py)
            near = np.nonzero(dist <= reach)[0]
            # Nearest first; the line-of-sight work below is done only on the candidates it
            # needs (with first_only, usually just the first chunk).
            order = near[np.argsort(dist[near], kind="stable")]
        if rank is not None and len(order):
            value = rank()[rr[order] + sl[0].start, cc[order] + sl[1].start]
            by = np.argsort(value, kind="stable")
            order = order[by[np.isfinite(value[by])]]
            first_only = True
        if first_only:
            for k in range(0, len(order), 64):  # nearest first: usually the first chunk has one
                chunk = order[k:k + 64]
                a, b = self._sight_segments(px[chunk], py[chunk], nearest[chunk])
                clear = None
                if k == 0:
                    # The nearest cells are usually in sight: check a few one by one (the
                    # vectorised check costs ~100 numpy calls however few segments it gets).
                    open_ = self._open_mask()
                    for i, (sa, sb) in enumerate(zip(a[:4].tolist(), b[:4].tolist())):
                        if _segment_clear(open_, sa[0], sa[1], sb[0], sb[1]):
                            clear = i
                            break
                    if clear is None and len(chunk) > 4:
                        found = self._wall_free(a[4:], b[4:])
                        clear = 4 + int(np.argmax(found)) if found.any() else None
                else:
                    found = self._wall_free(a, b)
                    clear = int(np.argmax(found)) if found.any() else None
                if clear is not None:
                    j = int(chunk[clear])
                    return (np.array([[rr[j] + sl[0].start, cc[j] + sl[1].start]]), dist[j:j + 1])
            return empty
        if len(order) == 0:
            return empty
        in_sight = self._wall_free(*self._sight_segments(px[order], py[order], nearest[order]))
        keep = order[in_sight]
        return np.column_stack([rr[keep] + sl[0].start, cc[keep] + sl[1].start]), dist[keep]

    def _nearest_if_in_sight(self, near: np.ndarray, within: np.ndarray, nx: np.ndarray, ny: np.ndarray,
                             xs: np.ndarray, ys: np.ndarray, sl) -> tuple[np.ndarray, np.ndarray] | None:
        """:meth:`reach_cells`'s answer with ``first_only`` for an axis-aligned footprint
        when its nearest candidate is in sight (usually so), found without sorting them
        all: the first minimum in row-major order is what the stable sort puts first.
        None when there is no candidate or the nearest is not in sight (the caller then
        looks further)."""
        k = int(np.argmin(np.where(near, within, np.inf)))
        r, c = divmod(k, near.shape[1])
        if not near[r, c]:
            return None
        if not _segment_clear(self._open_mask(), *self._sight_segment(float(xs[0, c]), float(ys[r, 0]),
                                                                     float(nx[c]), float(ny[r]))):
            return None
        return np.array([[r + sl[0].start, c + sl[1].start]]), within[r, c:c + 1].copy()

    def _component_mask(self, component: int) -> np.ndarray:
        """Walkable cells of one connected component (cached per component)."""
        mask = self._component_masks.get(component)
        if mask is None:
            mask = self._component_masks[component] = self.walkable & (self.labels == component)
        return mask

    def _sight_segment(self, px: float, py: float, qx: float, qy: float) -> tuple[float, float, float, float]:
        """:meth:`_sight_segments` of one cell centre and its nearest point (qx, qy), in
        scalar arithmetic (the same operations, so the same floats): (ax, ay, bx, by)."""
        ox, oy, res = self.origin[0], self.origin[1], self.resolution
        ax, ay = (px - ox) / res, (py - oy) / res
        bx, by = (qx - ox) / res, (qy - oy) / res
        dx, dy = ax - bx, ay - by
        pull = min(1.0, 1.5 / max(float(np.hypot(dx, dy)), 1e-9))
        return ax, ay, bx + dx * pull, by + dy * pull

    def _sight_segments(self, px: np.ndarray, py: np.ndarray, nearest: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Grid-coordinate segments from cell centres (px, py) toward their nearest points on
        a footprint, whose wall crossings decide whether the footprint is in sight."""
        a = np.column_stack([(px - self.origin[0]) / self.resolution, (py - self.origin[1]) / self.resolution])
        b = np.column_stack([(nearest[:, 0] - self.origin[0]) / self.resolution,
                             (nearest[:, 1] - self.origin[1]) / self.resolution])
        # Pull the far end back by 1.5 cells: a footprint's back stands a few centimetres
        # from a wall face, inside the wall's raster band.
        gap = np.hypot(*(a - b).T)
        b = b + (a - b) * np.minimum(1.0, 1.5 / np.maximum(gap, 1e-9))[:, None]
        return a, b

    def standing_point(self, object_id: int | np.ndarray, reach: float = 1.0,
                       start: Sequence[float] | None = None) -> XY | None:
        """A walkable point from which the object's footprint is within ``reach`` metres
        (horizontally) with no wall between. With ``start``: the one geodesically nearest
        to ``start`` (among points reachable from it); else the one nearest the object.
        ``object_id`` may also be a (4, 2) array of footprint corners. ``None`` if none."""
        corners = self.footprint(object_id) if isinstance(object_id, int | np.integer) else np.asarray(object_id)
        component = None
        if start is not None:
            component = self.component(start)
            if component == 0:
                return None
        cells, _ = self.reach_cells(corners, reach, component)
        if len(cells) == 0:
            return None
        if start is None:
            return self.to_world(cells[0])
        field = self.distance_field(start)
        best = int(np.argmin(field[cells[:, 0], cells[:, 1]]))
        return self.to_world(cells[best])


def _segments_clear(mask: np.ndarray, a: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Whether each segment ``a[i] -> targets[i]`` (grid coordinates: x = column, y = row;
    ``a`` may be one point for all) lies in cells where ``mask`` is true: every cell the
    segment enters is found from its crossings of the grid lines (an exact supercover,
    vectorised). Cells touched only at a corner point are ignored."""
    return _padded_segments_clear(_padded(mask), a, targets)


def _padded(mask: np.ndarray) -> np.ndarray:
    """``mask`` with a border of false cells: an index clipped into the border looks up a
    cell outside the grid."""
    out = np.zeros((mask.shape[0] + 2, mask.shape[1] + 2), dtype=bool)
    out[1:-1, 1:-1] = mask
    return out


def _padded_segments_clear(padded: np.ndarray, a: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """:func:`_segments_clear` on the :func:`_padded` mask."""
    h, w = padded.shape[0] - 2, padded.shape[1] - 2
    stride = w + 2
    flat = padded.ravel()
    t = np.asarray(targets, dtype=np.float64).reshape(-1, 2)
    s = np.broadcast_to(np.asarray(a, dtype=np.float64), t.shape)
    low, high = np.minimum(s, t), np.maximum(s, t)
    # With every end in the grid (or on its far edges), every cell looked up for a segment
    # lies in the padded grid (its border at worst), so no index needs clipping; the cells
    # looked up past a segment's last crossing are masked out whatever they hold.
    inside = len(t) > 0 and low.min() >= 0.0 and high[:, 0].max() <= w and high[:, 1].max() <= h

    def lookup(rows: np.ndarray, cols: np.ndarray, valid: np.ndarray) -> np.ndarray:
        # Rows and columns clipped to -1..h and -1..w: the border answers false outside.
        at = (np.minimum(np.maximum(rows, -1), h) + 1) * stride + np.minimum(np.maximum(cols, -1), w) + 1
        return (flat.take(at) | ~valid).all(axis=-1)

    if inside:
        ends = np.floor(np.concatenate([s, t])).astype(np.int64)
        at = (ends[:, 1] + 1) * stride + ends[:, 0] + 1
        ok = flat.take(at[:len(t)]) & flat.take(at[len(t):])
    else:
        one = np.ones((len(t), 1), dtype=bool)
        ok = lookup(np.floor(s[:, 1:2]).astype(np.int64), np.floor(s[:, 0:1]).astype(np.int64), one)
        ok &= lookup(np.floor(t[:, 1:2]).astype(np.int64), np.floor(t[:, 0:1]).astype(np.int64), one)
    for axis in (0, 1):  # crossings of vertical (x = k) then horizontal (y = k) grid lines
        other = 1 - axis
        lo, hi = low[:, axis], high[:, axis]
        first = np.floor(lo) + 1.0
        count = np.maximum((np.ceil(hi) - first).astype(np.int64), 0)  # lines inside (lo, hi)
        kmax = int(count.max()) if len(count) else 0
        if kmax == 0:
            continue
        steps = np.arange(kmax)
        ks = first[:, None] + steps[None, :]
        valid = steps[None, :] < count[:, None]
        d = t[:, axis] - s[:, axis]
        frac = (ks - s[:, axis:axis + 1]) / np.where(np.abs(d) < 1e-12, 1.0, d)[:, None]
        cross = s[:, other:other + 1] + frac * (t[:, other] - s[:, other])[:, None]
        line = np.floor(cross).astype(np.int64)
        k = ks.astype(np.int64)
        if inside:
            # The two cells either side of each crossing: (line, k - 1) and (line, k) of a
            # vertical line, (k - 1, line) and (k, line) of a horizontal one.
            at = (line + 1) * stride + k + 1 if axis == 0 else (k + 1) * stride + line + 1
            before = flat.take(at - (1 if axis == 0 else stride), mode="clip")
            ok &= ((before & flat.take(at, mode="clip")) | ~valid).all(axis=-1)
        elif axis == 0:
            ok &= lookup(line, k - 1, valid) & lookup(line, k, valid)
        else:
            ok &= lookup(k - 1, line, valid) & lookup(k, line, valid)
    return ok


def _segment_clear(mask: np.ndarray, sx: float, sy: float, tx: float, ty: float) -> bool:
    """:func:`_segments_clear` for one segment, in scalar arithmetic: the same operations
    in the same order (so the same answer), ~10x cheaper for a single segment."""
    h, w = mask.shape

    def ok(row: int, col: int) -> bool:
        return 0 <= row < h and 0 <= col < w and bool(mask[row, col])

    if not ok(math.floor(sy), math.floor(sx)) or not ok(math.floor(ty), math.floor(tx)):
        return False
    for s_a, t_a, s_o, t_o, vertical in ((sx, tx, sy, ty, True), (sy, ty, sx, tx, False)):
        lo, hi = min(s_a, t_a), max(s_a, t_a)
        first = math.floor(lo) + 1.0
        count = max(int(math.ceil(hi) - first), 0)  # grid lines inside (lo, hi)
        if count == 0:
            continue
        d = t_a - s_a
        denom = 1.0 if abs(d) < 1e-12 else d
        span = t_o - s_o
        for i in range(count):
            k = first + i
            line = math.floor(s_o + ((k - s_a) / denom) * span)
            ki = int(k)
            if vertical:
                if not (ok(line, ki - 1) and ok(line, ki)):
                    return False
            elif not (ok(ki - 1, line) and ok(ki, line)):
                return False
    return True


def _fill_walls(raster: Raster, walls: np.ndarray, obstacles: np.ndarray, scene: Scene) -> None:
    doors_by_wall: dict[str, list[Door]] = {}
    for door in scene.doors:
        doors_by_wall.setdefault(door.wall, []).append(door)
    min_half = 0.75 * raster.res  # keep thin walls at least two cells thick
    for wall in scene.walls:
        start, u, _, length = wall_frame(wall)
        half_t = max(wall.thickness / 2, min_half)
        doors = doors_by_wall.get(wall.id, [])
        for a, b in wall_solid_spans(wall, doors):
            # Extend true wall ends by half a thickness so corners close.
            a2 = a - wall.thickness / 2 if a <= 1e-9 else a
            b2 = b + wall.thickness / 2 if b >= length - 1e-9 else b
            raster.fill_oriented_rect(walls, start, u, (a2, b2), (-half_t, half_t))
        for door in doors:
            if door.leaf and door_passable(door):
                hinge, tip = door_leaf_open_segment(wall, door)
                d = tip - hinge
                half = leaf_half_thickness(raster.res)
                raster.fill_oriented_rect(obstacles, hinge, d / np.hypot(*d), (0.0, door.width), (-half, half))
