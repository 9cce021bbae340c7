"""How far an avatar can walk: its body against the world's collision geometry.

An avatar is a vertical disc of radius ``r`` swept across the floor. It collides with the
horizontal box of every collision geom that reaches into its height band (``z_range``): the
geom's own bounding box, turned with it when it turns about the vertical only (walls,
furniture, open door leaves), else its world-axis box. So a sofa's seat, a coffee table's
top and a bed frame block at every height of the band, not only where a few rays would
pass (the model this replaced: fifteen ``mj_ray`` casts at three heights, which walked
through the seat of a sofa and under a table top).

:meth:`ClearanceMap.sweep` finds the first contact exactly (a ray against each box grown
by ``r`` with rounded corners). Most moves cross open floor, so a raster of the same boxes
keeps each cell's distance to the nearest occupied cell, and :meth:`segment_clear` proves
with a few look-ups that a move touches nothing; only the others are swept.

Geoms of bodies welded to the world (walls, furniture) are taken once; geoms that can move
(small objects, door leaves, drawers) again when their poses change.
"""

from __future__ import annotations

import math
import weakref
from typing import NamedTuple, cast

import numpy as np

from legent_gym.world.builder import GROUP_COLLISION, World

#: Cell size of the map, metres.
RESOLUTION = 0.05
#: Added around every rasterised box: a contact on a box's face must not fall between cells.
BOX_MARGIN = 1e-6
#: A cell's distance to the nearest occupied cell bounds the distance from any point in it
#: to any box from below, less one cell diagonal (both points may be anywhere in their
#: cells), less a little for the float32 distances.
_CELL_SLACK = math.sqrt(2.0) + 1e-3


class BoxSet(NamedTuple):
    """Oriented horizontal boxes: columns for the vectorised prefilter of a sweep, and the
    same values as per-box tuples for its exact scalar tests (indexing a list of floats is
    several times cheaper than taking numpy scalars out of arrays)."""

    cx: np.ndarray
    cy: np.ndarray
    cos: np.ndarray
    sin: np.ndarray
    hx: np.ndarray  # half sizes along the box's own axes
    hy: np.ndarray
    bound: np.ndarray  # bounding-circle radius
    rows: list[tuple[float, float, float, float, float, float]]  # (cx, cy, cos, sin, hx, hy)

    @classmethod
    def from_rows(cls, rows: np.ndarray) -> BoxSet:
        """From an (n, 7) array of :meth:`ClearanceMap._oriented_boxes` rows."""
        cx, cy, cos, sin, hx, hy, bound = (np.ascontiguousarray(column) for column in rows.T)
        per_box = cast(list[tuple[float, float, float, float, float, float]],  # six columns
                       [tuple(r) for r in rows[:, :6].tolist()])
        return cls(cx, cy, cos, sin, hx, hy, bound, per_box)


class ClearanceMap:
    """The collision boxes in a height band (``z_range``), and each cell's distance to them."""

    def __init__(self, world: World, z_range: tuple[float, float]):
        model = world.model
        # A proxy: the map lives in world.derived, and a strong reference back would make
        # the world a cycle, freed (with its MuJoCo model and data) only by a full collection.
        self.world = cast(World, weakref.proxy(world))
        self.z_range = (z_range[0] - BOX_MARGIN, z_range[1] + BOX_MARGIN)
        collision = np.nonzero(model.geom_group == GROUP_COLLISION)[0]
        welded = model.body_weldid[model.geom_bodyid[collision]] == 0
        self._static_geoms = collision[welded]
        self._moving_geoms = collision[~welded]
        # Whether moving geoms moved is read off their bodies' poses (geom poses follow from
        # them in the same kinematics pass), over one slice of bodies holding every moving
        # one: a copy of contiguous memory, far cheaper than gathering geoms.
        bodies = model.geom_bodyid[self._moving_geoms]
        self._span = (int(bodies.min()), int(bodies.max()) + 1) if len(bodies) else (0, 0)
        (x0, y0), (x1, y1) = world.scene.bounds()
        margin = 2.0
        self.origin = (x0 - margin, y0 - margin)
        self.shape = (int(math.ceil((y1 - y0 + 2 * margin) / RESOLUTION)),
                      int(math.ceil((x1 - x0 + 2 * margin) / RESOLUTION)))
        self._static_boxes = self._oriented_boxes(self._static_geoms)
        self._static = np.zeros(self.shape, dtype=bool)
        # The border counts as occupied: a box (partly) outside the map is never missed.
        self._static[[0, -1], :] = True
        self._static[:, [0, -1]] = True
        self._rasterise(self._static, self._static_geoms)
        #: excluded body -> (poses of the moving geoms it was made for, distance map, boxes)
        self._maps: dict[int, tuple[bytes, np.ndarray, BoxSet]] = {}

    # -- building -----------------------------------------------------------------------
    def _frames(self, geoms: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(rotations, box centres, local half sizes, world-axis half sizes) of geoms'
        bounding boxes."""
        model, data = self.world.model, self.world.data
        rot = data.geom_xmat[geoms].reshape(-1, 3, 3)
        half = model.geom_aabb[geoms, 3:]
        centre = data.geom_xpos[geoms] + np.einsum("nij,nj->ni", rot, model.geom_aabb[geoms, :3])
        return rot, centre, half, np.einsum("nij,nj->ni", np.abs(rot), half)

    def _boxes(self, geoms: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World axis-aligned boxes (lo, hi) of geoms, from their local bounding boxes."""
        _, centre, _, world_half = self._frames(geoms)
        world_half = world_half + BOX_MARGIN
        return centre - world_half, centre + world_half

    def _oriented_boxes(self, geoms: np.ndarray) -> np.ndarray:
        """(n, 7) rows ``cx, cy, cos, sin, half_x, half_y, bounding radius``: the horizontal
        box of every geom reaching into the height band, turned with the geom if it turns
        about z only, else its world-axis box."""
        if len(geoms) == 0:
            return np.zeros((0, 7))
        rot, centre, half, world_half = self._frames(geoms)
        z0, z1 = self.z_range
        keep = (centre[:, 2] + world_half[:, 2] >= z0) & (centre[:, 2] - world_half[:, 2] <= z1)
        upright = np.abs(rot[:, 2, 2]) > 1.0 - 1e-6
        cos = np.where(upright, rot[:, 0, 0], 1.0)
        sin = np.where(upright, rot[:, 1, 0], 0.0)
        hx = np.where(upright, half[:, 0], world_half[:, 0])
        hy = np.where(upright, half[:, 1], world_half[:, 1])
        return np.stack([centre[:, 0], centre[:, 1], cos, sin, hx, hy, np.hypot(hx, hy)], axis=1)[keep]

    def _rasterise(self, occupied: np.ndarray, geoms: np.ndarray) -> None:
        """Mark every cell that a geom's box overlaps (geoms reaching into the band)."""
        if len(geoms) == 0:
            return
        lo, hi = self._boxes(geoms)
        z0, z1 = self.z_range
        keep = (hi[:, 2] >= z0) & (lo[:, 2] <= z1)
        h, w = self.shape
        ox, oy = self.origin
        for (ax, ay, _), (bx, by, _) in zip(lo[keep].tolist(), hi[keep].tolist()):
            c0 = max(int(math.floor((ax - ox) / RESOLUTION)), 0)
            c1 = min(int(math.floor((bx - ox) / RESOLUTION)), w - 1)
            r0 = max(int(math.floor((ay - oy) / RESOLUTION)), 0)
            r1 = min(int(math.floor((by - oy) / RESOLUTION)), h - 1)
            if c0 <= c1 and r0 <= r1:
                occupied[r0:r1 + 1, c0:c1 + 1] = True

    def snapshot(self, exclude_body: int) -> tuple[np.ndarray, BoxSet]:
        """(distance map, oriented boxes) ignoring ``exclude_body`` (-1: none), rebuilt when
        moving geoms moved. The map holds each cell centre's distance (cells) to the nearest
        occupied cell centre; the boxes are those of :meth:`_oriented_boxes`."""
        state = self._state(exclude_body)
        return state[1], state[2]

    def _state(self, exclude_body: int) -> tuple[bytes, np.ndarray, BoxSet]:
        model, data = self.world.model, self.world.data
        lo, hi = self._span
        # The excluded body (a held object) moves with whoever holds it: leave it out.
        cut = min(max(exclude_body, lo), hi) if exclude_body >= 0 else hi
        end = min(cut + 1, hi)
        poses = (data.xpos[lo:cut].tobytes() + data.xpos[end:hi].tobytes()
                 + data.xquat[lo:cut].tobytes() + data.xquat[end:hi].tobytes())
        hit = self._maps.get(exclude_body)
        if hit is not None and hit[0] == poses:
            return hit
        moving = self._moving_geoms
        if exclude_body >= 0:
            moving = moving[model.geom_bodyid[moving] != exclude_body]
        occupied = self._static.copy()
        self._rasterise(occupied, moving)
        import cv2  # a core dependency, imported when first needed

        dist = cv2.distanceTransform((~occupied).view(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
        boxes = np.concatenate([self._static_boxes, self._oriented_boxes(moving)])
        state = (poses, dist, BoxSet.from_rows(boxes))
        if len(self._maps) >= 4:  # the agent's and the user's (each holding or not)
            self._maps.clear()
        self._maps[exclude_body] = state
        return state

    # -- queries ------------------------------------------------------------------------
    def segment_clear(self, dist: np.ndarray, x: float, y: float, fx: float, fy: float, length: float,
                      half_width: float) -> bool:
        """Whether the strip from (x, y) along the unit direction (fx, fy), ``length`` long
        and ``half_width`` to either side, is certainly clear of every box (False: maybe not).

        Steps along the centre line: at a point whose clearance bound is ``c``, the strip is
        clear for ``sqrt(c^2 - half_width^2)`` ahead and behind.
        """
        h, w = self.shape
        ox, oy = self.origin
        along = 0.0
        while True:
            px, py = x + fx * along, y + fy * along
            col = math.floor((px - ox) / RESOLUTION)
            row = math.floor((py - oy) / RESOLUTION)
            if not (0 <= row < h and 0 <= col < w):
                return False
            c = (float(dist[row, col]) - _CELL_SLACK) * RESOLUTION
            if c <= half_width:
                return False
            step = math.sqrt(c * c - half_width * half_width) * 0.999
            if along + step >= length:
                return True
            if step < 0.5 * RESOLUTION:  # creeping past an obstacle: let the exact sweep decide
                return False
            along += step

    @staticmethod
    def sweep(boxes: BoxSet, x: float, y: float, fx: float, fy: float, length: float, radius: float) -> float:
        """How far a disc of ``radius`` at (x, y) moves along the unit direction (fx, fy)
        before it touches a box (``inf`` if not within ``length``).

        A box the disc already overlaps blocks only a move that goes deeper into it (so an
        avatar pushed against something can always back away).
        """
        # Boxes whose bounding circle comes within reach of the swept strip, then each exactly.
        rx, ry = boxes.cx - x, boxes.cy - y
        along = rx * fx + ry * fy
        reach = boxes.bound + radius
        near = np.nonzero((np.abs(rx * fy - ry * fx) <= reach) & (along >= -reach) & (along <= length + reach))[0]
        best = math.inf
        rows = boxes.rows
        inf = math.inf
        for i in near.tolist():
            bcx, bcy, c, s, bx, by = rows[i]
            ox, oy = x - bcx, y - bcy
            px, py = c * ox + s * oy, c * oy - s * ox  # the start in the box's frame
            dx, dy = c * fx + s * fy, c * fy - s * fx  # the direction in the box's frame
            # When the centre is inside the box grown by the radius: an interval of t per
            # axis (slab), intersected; inlined, as this loop is the hottest of a step.
            gx, gy = bx + radius, by + radius
            if dx != 0.0:
                t1, t2 = (-gx - px) / dx, (gx - px) / dx
                enter, leave = (t1, t2) if t1 <= t2 else (t2, t1)
            elif abs(px) <= gx:
                enter, leave = -inf, inf
            else:
                continue
            if dy != 0.0:
                t1, t2 = (-gy - py) / dy, (gy - py) / dy
                if t1 > t2:
                    t1, t2 = t2, t1
                if t1 > enter:
                    enter = t1
                if t2 < leave:
                    leave = t2
            elif abs(py) > gy:
                continue
            if enter > leave or leave < 0.0 or enter > length:
                continue  # the centre never enters the box grown by the radius
            contact = _contact(px, py, dx, dy, bx, by, radius, enter)
            if contact < best:
                best = contact
        return best if best <= length else math.inf


def _contact(px: float, py: float, dx: float, dy: float, hx: float, hy: float, radius: float,
             enter: float) -> float:
    """First ``t >= 0`` at which the disc at (px, py) + t (dx, dy) touches the box
    [-hx, hx] x [-hy, hy] (box frame), given when its centre enters the grown box; inf if
    never or if it already overlaps the box and does not go deeper."""
    if enter >= 0.0:
        qx, qy = px + enter * dx, py + enter * dy
        if abs(qx) <= hx or abs(qy) <= hy:
            return enter  # enters through a side: the disc touches a face there
        corner_x, corner_y = math.copysign(hx, qx), math.copysign(hy, qy)
    else:
        gx, gy = px - min(max(px, -hx), hx), py - min(max(py, -hy), hy)
        if gx * gx + gy * gy <= radius * radius:  # already touching
            return 0.0 if gx * dx + gy * dy < 0.0 else math.inf
        corner_x, corner_y = math.copysign(hx, px), math.copysign(hy, py)
    # Through a corner square of the grown box: it touches only if it meets the corner's circle.
    wx, wy = px - corner_x, py - corner_y
    b = wx * dx + wy * dy
    disc = b * b - (wx * wx + wy * wy - radius * radius)
    if disc < 0.0:
        return math.inf
    t = -b - math.sqrt(disc)
    return t if t >= 0.0 else math.inf
