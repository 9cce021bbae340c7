"""Which of a move's collision rays can hit anything: a clearance map of the world's
collision geometry, so that :meth:`Body.free_distance` casts only the rays that might.

A ray cast (``mj_ray``) tests every geom of the model, and a move casts fifteen of them.
Most moves cross open floor. This map rasterises the horizontal bounding box of every
collision geom that reaches the rays' heights (a hit point always lies inside its geom's
box) and keeps each cell's distance to the nearest occupied cell. A ray whose whole segment
stays clear of every box by that bound cannot hit anything within the length that matters,
so skipping it changes nothing: the result is exactly that of casting all fifteen.

Geoms of bodies welded to the world (walls, furniture) are rasterised once; geoms that can
move (small objects, door leaves, drawers) are re-rasterised when their poses change.
"""

from __future__ import annotations

import math

import numpy as np

from legent_gym.world.builder import GROUP_COLLISION, World

#: Cell size of the map, metres.
RESOLUTION = 0.05
#: Added around every box: mj_ray's hit points lie on the geom up to rounding.
BOX_MARGIN = 1e-6
#: A cell's distance to the nearest occupied cell bounds the distance from any point in it
#: to any box from below, less one cell diagonal (both points may be anywhere in their
#: cells), less a little for the float32 distances.
_CELL_SLACK = math.sqrt(2.0) + 1e-3


class ClearanceMap:
    """Distance from each cell to the collision geometry at the rays' heights (``z_range``)."""

    def __init__(self, world: World, z_range: tuple[float, float]):
        model = world.model
        self.world = world
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
        self._static = np.zeros(self.shape, dtype=bool)
        # The border counts as occupied: a box (partly) outside the map is never missed.
        self._static[[0, -1], :] = True
        self._static[:, [0, -1]] = True
        self._rasterise(self._static, self._static_geoms)
        #: excluded body -> (poses of the moving geoms it was made for, distance map)
        self._maps: dict[int, tuple[bytes, np.ndarray]] = {}

    # -- building -----------------------------------------------------------------------
    def _boxes(self, geoms: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World axis-aligned boxes (lo, hi) of geoms, from their local bounding boxes."""
        model, data = self.world.model, self.world.data
        rot = data.geom_xmat[geoms].reshape(-1, 3, 3)
        centre = data.geom_xpos[geoms] + np.einsum("nij,nj->ni", rot, model.geom_aabb[geoms, :3])
        half = np.einsum("nij,nj->ni", np.abs(rot), model.geom_aabb[geoms, 3:]) + BOX_MARGIN
        return centre - half, centre + half

    def _rasterise(self, occupied: np.ndarray, geoms: np.ndarray) -> None:
        """Mark every cell that a geom's box overlaps (at the rays' heights)."""
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

    def distances(self, exclude_body: int) -> np.ndarray:
        """Distance (cells) from each cell centre to the nearest occupied cell centre, for
        rays that ignore ``exclude_body`` (-1: none); rebuilt when moving geoms moved."""
        model, data = self.world.model, self.world.data
        lo, hi = self._span
        # The excluded body (a held object) moves with whoever holds it: leave it out.
        cut = min(max(exclude_body, lo), hi) if exclude_body >= 0 else hi
        end = min(cut + 1, hi)
        poses = (data.xpos[lo:cut].tobytes() + data.xpos[end:hi].tobytes()
                 + data.xquat[lo:cut].tobytes() + data.xquat[end:hi].tobytes())
        hit = self._maps.get(exclude_body)
        if hit is not None and hit[0] == poses:
            return hit[1]
        moving = self._moving_geoms
        if exclude_body >= 0:
            moving = moving[model.geom_bodyid[moving] != exclude_body]
        occupied = self._static.copy()
        self._rasterise(occupied, moving)
        import cv2  # a core dependency, imported when first needed

        dist = cv2.distanceTransform((~occupied).view(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
        if len(self._maps) >= 4:  # the agent's and the user's (each holding or not)
            self._maps.clear()
        self._maps[exclude_body] = (poses, dist)
        return dist

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
            if step < 0.5 * RESOLUTION:  # creeping past an obstacle: let the rays decide
                return False
            along += step
