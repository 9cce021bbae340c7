"""Furniture: what goes in each room type, and where.

Each room type has priority pieces (a bedroom's bed, a kitchen's fridge and counter, ...)
and optional ones with probabilities. A piece is anchored by its asset's ``placement``
annotation: ``wall`` (back to a wall, front into the room), ``corner`` (flush in a convex
corner) or ``middle`` (in open floor, preferring the most open spot). Some pieces come as
groups placed as one unit: bed + nightstands, sofa + coffee table, desk + chair, dining
table + chairs facing it, tv stand + tv on top.

Pieces are axis-aligned (yaw a multiple of 90 degrees), so every footprint is an
axis-aligned rectangle (``x0, y0, x1, y1``) and candidate poses are checked in bulk with
numpy: inside the room's inner outline (the polygon inset by half a wall), clear of other
pieces by a margin, of every piece's front clearance zone, of the free squares in front of
doors, and (for tall pieces) of windows. After each accepted piece a small raster of the
room checks that the agent can still walk between the room's doors and reach every piece.

Phases: priority pieces in every room, then what the conditions still need, then optional
pieces, then surface pieces on free supports (a microwave on a kitchen counter); so
conditions get space before decoration does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.assets.model import AssetModel, Receptacle
from legent_gym.world.generation.conditions import Catalog
from legent_gym.world.generation.floorplan import WALL_THICKNESS, FloorPlan
from legent_gym.world.generation.roomtypes import ROOM_TYPES
from legent_gym.world.geometry import (
    HANGING_HEIGHT,
    QUARTER_TURNS,
    bounding_box,
    door_keepout_squares,
    door_leaf_open_segment,
    door_passable,
    expand,
    inset_polygon,
    local_footprint,
    opening_span,
    overlap_matrix,
    points_in_polygon,
    quarter_turns_facing,
    rects_in_polygon,
    turn_cross,
    turned_rect,
    wall_frame,
)
from legent_gym.world.navigation import (
    Raster,
    label_regions,
    leaf_half_thickness,
    least_square_distance,
    walkable_from_free,
)

EPS = 1e-6
#: Gap between a piece's back and the wall face, and from a corner.
WALL_GAP = 0.03
#: Gap between members of a group (nightstand to bed, chair to table).
GROUP_GAP = 0.05
#: Depth of the no-tall-furniture zone in front of a window.
WINDOW_DEPTH = 0.35
#: How far above a window's sill a piece may reach and still stand in front of it (a bed's
#: headboard may; a wardrobe may not).
WINDOW_TOLERANCE = 0.3
AGENT_RADIUS = 0.25
#: Reach used while furnishing: a little under the 1.0 m of the final check.
REACH = 0.9
#: Largest walkable area (m^2) a room may leave cut off from its doors.
POCKET_AREA = 0.5
#: Extra agent radius while furnishing, so borderline gaps pass the final check too.
CHECK_MARGIN = 0.03


class PlacementFailed(Exception):
    """A piece the house must have does not fit (the caller retries or reports).
    ``category`` names the furniture category a condition asked for, if that failed."""

    def __init__(self, message: str, category: str | None = None):
        super().__init__(message)
        self.category = category


@dataclass(frozen=True)
class Rule:
    category: str
    p: float = 1.0
    count: tuple[int, int] = (1, 1)
    group: str | None = None


#: Per room type: (priority pieces, optional pieces). Optional pieces are tried in this
#: order, so the pieces that define a room (a kitchen's stove, a hallway's coat rack) get
#: their space before the decoration.
ROOM_FURNITURE: dict[str, tuple[list[Rule], list[Rule]]] = {
    "bedroom": (
        [Rule("bed", group="bed")],
        [Rule("wardrobe", 0.55), Rule("dresser", 0.5), Rule("desk", 0.25, group="desk"),
         Rule("plant", 0.35), Rule("floor_lamp", 0.3), Rule("bookshelf", 0.35), Rule("armchair", 0.2),
         Rule("tv_stand", 0.15, group="tv"), Rule("side_table", 0.15), Rule("sofa", 0.1), Rule("chair", 0.1),
         Rule("chest", 0.2), Rule("standing_mirror", 0.15), Rule("laundry_hamper", 0.15), Rule("radiator", 0.1),
         Rule("ottoman", 0.1), Rule("floor_fan", 0.08)],
    ),
    "living_room": (
        [Rule("sofa", group="sofa")],
        [Rule("tv_stand", 0.8, group="tv"), Rule("armchair", 0.6, (1, 2)), Rule("fireplace", 0.2),
         Rule("bookshelf", 0.65), Rule("plant", 0.6, (1, 2)), Rule("floor_lamp", 0.4), Rule("side_table", 0.4),
         Rule("ottoman", 0.3), Rule("sideboard", 0.2), Rule("dining_table", 0.15, group="dining"),
         Rule("dresser", 0.15), Rule("desk", 0.1, group="desk"), Rule("piano", 0.08), Rule("aquarium", 0.08),
         Rule("storage_cabinet", 0.15), Rule("console_table", 0.15), Rule("radiator", 0.2), Rule("trash_can", 0.1),
         Rule("floor_fan", 0.08), Rule("grandfather_clock", 0.06), Rule("chest", 0.05), Rule("stool", 0.05)],
    ),
    "kitchen": (
        [Rule("fridge"), Rule("kitchen_counter")],
        [Rule("stove", 0.9), Rule("kitchen_counter", 0.5), Rule("sink", 0.5), Rule("dishwasher", 0.45),
         Rule("pantry_cabinet", 0.3), Rule("kitchen_island", 0.2), Rule("dining_table", 0.35, group="dining"),
         Rule("trash_can", 0.5), Rule("bar_stool", 0.2, (1, 2)), Rule("plant", 0.2), Rule("chair", 0.1),
         Rule("washing_machine", 0.1), Rule("stool", 0.1), Rule("radiator", 0.1)],
    ),
    "bathroom": (
        [Rule("toilet")],
        [Rule("sink", 0.55), Rule("vanity", 0.5), Rule("bathtub", 0.45), Rule("shower", 0.4),
         Rule("towel_rack", 0.3), Rule("washing_machine", 0.2), Rule("laundry_hamper", 0.25), Rule("trash_can", 0.3),
         Rule("radiator", 0.2), Rule("dryer", 0.1), Rule("plant", 0.1)],
    ),
    "dining_room": (
        [Rule("dining_table", group="dining")],
        [Rule("sideboard", 0.4), Rule("dresser", 0.3), Rule("bookshelf", 0.3), Rule("plant", 0.5),
         Rule("floor_lamp", 0.2), Rule("side_table", 0.2), Rule("kitchen_counter", 0.1), Rule("storage_cabinet", 0.15),
         Rule("grandfather_clock", 0.1), Rule("radiator", 0.15), Rule("bench", 0.1), Rule("aquarium", 0.05),
         Rule("bar_stool", 0.05)],
    ),
    "office": (
        [Rule("desk", group="desk")],
        [Rule("bookshelf", 0.8, (1, 2)), Rule("filing_cabinet", 0.45), Rule("armchair", 0.3), Rule("plant", 0.5),
         Rule("floor_lamp", 0.3), Rule("trash_can", 0.4), Rule("side_table", 0.2), Rule("sofa", 0.15, group="sofa"),
         Rule("dresser", 0.15), Rule("storage_cabinet", 0.2), Rule("radiator", 0.15), Rule("floor_fan", 0.1),
         Rule("aquarium", 0.05), Rule("stool", 0.05)],
    ),
    "hallway": (
        [],
        [Rule("coat_rack", 0.4), Rule("shoe_rack", 0.4), Rule("console_table", 0.3), Rule("umbrella_stand", 0.3),
         Rule("bench", 0.25), Rule("side_table", 0.3), Rule("plant", 0.4), Rule("dresser", 0.2),
         Rule("bookshelf", 0.15), Rule("standing_mirror", 0.15), Rule("storage_cabinet", 0.1),
         Rule("radiator", 0.15), Rule("grandfather_clock", 0.08), Rule("chair", 0.1)],
    ),
}

#: Per room type: surface pieces stood on a free support of the room (see SUPPORTS), each
#: with its probability, after the floor pieces: a kitchen's microwave on a counter.
ROOM_SURFACE_PIECES: dict[str, list[Rule]] = {
    "kitchen": [Rule("microwave", 0.6), Rule("coffee_machine", 0.4), Rule("toaster", 0.3)],
}
#: Per room type: the probability that it has pictures on its walls, and how many then.
WALL_DECOR: dict[str, tuple[float, tuple[int, int]]] = {
    "living_room": (0.85, (1, 3)), "bedroom": (0.75, (1, 2)), "dining_room": (0.75, (1, 2)),
    "office": (0.6, (1, 2)), "hallway": (0.5, (1, 2)), "kitchen": (0.25, (1, 1)),
}
#: A hung picture's centre (metres above the floor, at a standing person's eye level), its
#: least clearance above the furniture under it and below the ceiling, and its least
#: distance from a window, a door, an open door leaf and another picture.
HANG_CENTRE = 1.5
HANG_ABOVE_FURNITURE = 0.15
HANG_BELOW_CEILING = 0.2
HANG_APART = 0.25
#: The probability that a desk's chair is an office chair (where there is one), per room type.
OFFICE_CHAIR_P = {"office": 0.6}
OFFICE_CHAIR_P_ELSEWHERE = 0.3

#: Group anchor -> the categories it may bring along.
GROUP_MEMBERS: dict[str, tuple[str, ...]] = {
    "bed": ("nightstand",),
    "sofa": ("coffee_table",),
    "desk": ("chair", "office_chair"),
    "dining": ("chair",),
    "tv": ("tv",),
}
#: Which group an anchor category forms when a condition asks for it on its own.
DEFAULT_GROUP = {"bed": "bed", "sofa": "sofa", "desk": "desk", "dining_table": "dining", "tv_stand": "tv"}
#: Surface furniture -> the categories it stands on.
SUPPORTS = {"tv": ("tv_stand", "dresser", "side_table"), "microwave": ("kitchen_counter",),
            "coffee_machine": ("kitchen_counter",), "toaster": ("kitchen_counter",)}
#: Probability of placing a user-registered category the tables do not know (if its
#: ``rooms`` annotation allows the room).
EXTRA_CATEGORY_P = 0.25


def allowed_room_types(catalog: Catalog, category: str) -> set[str]:
    """Room types a category may be placed in: the tables above plus the asset's own
    ``rooms`` annotation (all types when neither says anything)."""
    types = set()
    for rtype, (prio, opt) in ROOM_FURNITURE.items():
        for rule in prio + opt:
            if rule.category == category or category in GROUP_MEMBERS.get(rule.group or "", ()):
                types.add(rtype)
            if category in SUPPORTS and rule.category in SUPPORTS[category]:
                types.add(rtype)
    if category in catalog.by_category:
        for asset_id in catalog.by_category[category]:
            types |= set(catalog.models[asset_id].rooms)
    return types or set(ROOM_FURNITURE)


# ---------------------------------------------------------------------------------------
# Placed pieces and rooms


@dataclass
class Placed:
    category: str
    asset: str
    variant: int
    x: float
    y: float
    q: int  #: yaw in quarter turns (counter-clockwise)
    model: AssetModel
    room: int
    group: int
    rect: np.ndarray  #: world footprint (x0, y0, x1, y1)
    front: np.ndarray | None  #: world front-clearance zone
    z: float = 0.0
    yaw: float | None = None  #: degrees; None means q * 90
    support: int | None = None  #: index (in the house's list) of the piece it stands on
    receptacle: int | None = None  #: which receptacle of the support
    required: bool = False
    #: The scene object's scale: a dressing piece stretched to fit (a rug, a wall cabinet).
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)

    @property
    def yaw_deg(self) -> float:
        return float(self.q * 90 % 360) if self.yaw is None else self.yaw

    @property
    def height(self) -> float:
        return float(self.model.size[2])

    @property
    def on_floor(self) -> bool:
        """Standing on the floor: neither on another piece, nor hung on a wall, nor a covering
        lying flat on it (a rug blocks no floor)."""
        return self.support is None and self.z < HANGING_HEIGHT and self.model.placement != "floor"

    @property
    def hanging(self) -> bool:
        """Hung on a wall above the floor (a picture, a wall cabinet)."""
        return self.support is None and self.z >= HANGING_HEIGHT


@dataclass
class Member:
    """A group member's pose in its anchor's frame."""

    category: str
    asset: str
    variant: int
    model: AssetModel
    dx: float
    dy: float
    dq: int


@dataclass
class RoomSpace:
    """A room as the furnisher sees it."""

    index: int
    rtype: str
    inner: np.ndarray  #: the floor polygon inset by half a wall (the free floor's outline)
    keepouts: np.ndarray  #: door squares (K, 4)
    windows: np.ndarray  #: (W, 5): zone rect + sill height
    margin: float
    #: Open door leaves swinging into this room, (hinge, tip) segments.
    leaves: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)
    #: Where the agent stands right after passing each door (K, 4).
    mouths: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    pieces: list[int] = field(default_factory=list)
    reach: RoomReach | None = None
    _edges: list | None = field(default=None, repr=False, compare=False)  # the inner outline is fixed
    _edge_arrays: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = field(
        default=None, repr=False, compare=False)

    @property
    def bbox(self) -> np.ndarray:
        return bounding_box(self.inner)

    def require_reach(self) -> RoomReach:
        """The room's reach check (made right after the space: it needs the space)."""
        if self.reach is None:
            raise RuntimeError(f"room {self.index} has no reach check yet")
        return self.reach

    def edges(self):
        """Inner wall edges: (start, unit direction, inward normal, length, start convex,
        end convex); counter-clockwise, so the inward normal is the left normal."""
        if self._edges is None:
            self._edges = self._compute_edges()
        return self._edges

    def edge_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`edges`' starts, directions and inward normals as (E, 2) arrays, and the
        quarter turns that face each normal (E,)."""
        if self._edge_arrays is None:
            edges = self.edges()
            self._edge_arrays = (np.array([e[0] for e in edges]).reshape(-1, 2),
                                 np.array([e[1] for e in edges]).reshape(-1, 2),
                                 np.array([e[2] for e in edges]).reshape(-1, 2),
                                 np.array([quarter_turns_facing(e[2]) for e in edges], dtype=np.float64))
        return self._edge_arrays

    def _compute_edges(self):
        poly = self.inner
        n = len(poly)
        out = []
        for k in range(n):
            p0, p1 = poly[k], poly[(k + 1) % n]
            d = p1 - p0
            length = float(np.hypot(*d))
            e = d / length
            conv0 = float(turn_cross(poly[k - 1], p0, p1)) > 0
            conv1 = float(turn_cross(p0, p1, poly[(k + 2) % n])) > 0
            out.append((p0, e, np.array([-e[1], e[0]]), length, conv0, conv1))
        return out


class RoomReach:
    """A small raster of one room: can the agent still walk between the doors and reach
    every piece?"""

    def __init__(self, space: RoomSpace, resolution: float = 0.05):
        bb = space.bbox
        pad = 0.1
        self.res = resolution
        # Cells on multiples of the resolution: the same cells as the house's navigation grid
        # (whose origin is the house corner minus a margin), so borderline gaps agree.
        x0 = np.floor((bb[0] - pad) / resolution + 1e-6) * resolution
        y0 = np.floor((bb[1] - pad) / resolution + 1e-6) * resolution
        shape = (int(np.ceil((bb[3] + pad - y0) / resolution)), int(np.ceil((bb[2] + pad - x0) / resolution)))
        self.raster = Raster((x0, y0), resolution, shape)
        self.floor = np.zeros(shape, dtype=bool)
        self.raster.fill_polygon(self.floor, space.inner)
        #: Outside the room's inner outline (what blocks reach in an L-shaped room).
        self.outside = ~self.floor
        self.concave = len(space.inner) > 4
        leaves = np.zeros(shape, dtype=bool)
        for hinge, tip in space.leaves:
            # The same slab the navigation grid uses for an open leaf.
            d = tip - hinge
            half = leaf_half_thickness(resolution)
            self.raster.fill_oriented_rect(leaves, hinge, d / np.hypot(*d), (0.0, float(np.hypot(*d))), (-half, half))
        self.floor &= ~leaves
        self.occupied = np.zeros(shape, dtype=bool)
        self.doors = [self._cells(r) for r in space.mouths]
        # Walkable floor is kept up to date as pieces come and go rather than recomputed
        # with a distance transform for every check: a cell is walkable when no blocked
        # cell lies within squared distance ``_n`` (cells) of it; squared distances between
        # cells are integers, so this is exactly ``walkable_from_free`` of the free floor.
        radius = AGENT_RADIUS + CHECK_MARGIN
        self._n = least_square_distance(radius + 0.5 * resolution, resolution)
        self._base_walk = walkable_from_free(self.floor, radius, resolution)
        self._near_pieces = np.zeros(shape, dtype=bool)
        #: target rectangle (bytes) -> a cell that reached it once
        self._witness: dict[bytes, tuple[int, int]] = {}

    def _cells(self, rect: np.ndarray):
        return self.raster.window(rect[0] + EPS, rect[1] + EPS, rect[2] - EPS, rect[3] - EPS)

    def add(self, rect: np.ndarray) -> None:
        """Mark a footprint: cells whose centre lies inside it."""
        win = self._cells(rect)
        if win is None:
            return
        sl, xs, ys = win
        inside_x = (xs[0] > rect[0]) & (xs[0] < rect[2])
        inside_y = (ys[:, 0] > rect[1]) & (ys[:, 0] < rect[3])
        self.occupied[sl] |= inside_y[:, None] & inside_x[None, :]
        if inside_x.any() and inside_y.any():
            cols, rows = np.nonzero(inside_x)[0] + sl[1].start, np.nonzero(inside_y)[0] + sl[0].start
            self._block_near(int(rows[0]), int(rows[-1]), int(cols[0]), int(cols[-1]))

    def _block_near(self, r0: int, r1: int, c0: int, c1: int) -> None:
        """Cells no longer walkable once cells r0..r1 x c0..c1 are blocked: those within
        squared distance ``_n`` (cells) of the block."""
        m = math.isqrt(max(self._n - 1, 0))
        h, w = self.occupied.shape
        rows = np.arange(max(r0 - m, 0), min(r1 + m + 1, h))
        cols = np.arange(max(c0 - m, 0), min(c1 + m + 1, w))
        if len(rows) == 0 or len(cols) == 0:
            return
        dy = np.maximum(np.maximum(r0 - rows, rows - r1), 0)
        dx = np.maximum(np.maximum(c0 - cols, cols - c1), 0)
        self._near_pieces[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1] |= (dy * dy)[:, None] + (dx * dx)[None, :] < self._n

    def clear(self) -> None:
        """Remove every footprint."""
        self.occupied[:] = False
        self._near_pieces[:] = False

    def walkable(self) -> np.ndarray:
        """Where the agent can stand: ``walkable_from_free(floor & ~occupied)``."""
        return self._base_walk & ~self._near_pieces

    def ok(self, targets: list[np.ndarray]) -> bool:
        """Doors linked by walkable floor, and each target rectangle within reach of it."""
        labels, n = label_regions(self.walkable())
        if n == 0:
            return False
        common: set[int] | None = None
        for win in self.doors:
            if win is None:
                continue
            here = labels[win[0]]
            found = set(here[here > 0].tolist())
            common = found if common is None else common & found
        if common is None:  # no door in this room: keep the largest walkable area
            common = {int(np.argmax(np.bincount(labels[labels > 0])))}
        if not common:
            return False
        main = labels == next(iter(common)) if len(common) == 1 else np.isin(labels, sorted(common))
        # No sizeable walkable pocket cut off from the doors (half a square metre).
        sizes = np.bincount(labels.ravel(), minlength=n + 1)
        sizes[sorted(common)] = 0
        if (sizes[1:] * self.res ** 2 > POCKET_AREA).any():
            return False
        return all(self._reachable(main, r) for r in targets)

    def _reachable(self, main: np.ndarray, rect: np.ndarray) -> bool:
        # A cell that reached this rectangle before still does while it is walkable and
        # linked to the doors (distance and sight do not change; only ``main`` shrinks).
        key = rect.tobytes()
        witness = self._witness.get(key)
        if witness is not None and main[witness]:
            return True
        win = self.raster.window(rect[0] - REACH, rect[1] - REACH, rect[2] + REACH, rect[3] + REACH)
        if win is None:
            return False
        sl, xs, ys = win
        nx = np.clip(xs, rect[0], rect[2])
        ny = np.clip(ys, rect[1], rect[3])
        near = main[sl] & ((nx - xs) ** 2 + (ny - ys) ** 2 <= REACH * REACH)
        if not near.any():
            return False
        if not self.concave:
            r, c = np.unravel_index(int(np.argmax(near)), near.shape)
            self._witness[key] = (int(r) + sl[0].start, int(c) + sl[1].start)
            return True
        # An L-shaped room: the reach must not pass behind its inner corner.
        rr, cc = np.nonzero(near)
        px, py = xs[0, cc], ys[rr, 0]
        qx, qy = np.broadcast_to(nx, near.shape)[rr, cc], np.broadcast_to(ny, near.shape)[rr, cc]
        t = np.linspace(0.0, 1.0, 24)[None, :]
        sx = px[:, None] + (qx - px)[:, None] * t * 0.97
        sy = py[:, None] + (qy - py)[:, None] * t * 0.97
        col = np.clip(((sx - self.raster.x0) / self.res).astype(np.int64), 0, self.outside.shape[1] - 1)
        row = np.clip(((sy - self.raster.y0) / self.res).astype(np.int64), 0, self.outside.shape[0] - 1)
        seen = ~self.outside[row, col].any(axis=1)
        if not seen.any():
            return False
        k = int(np.argmax(seen))
        self._witness[key] = (int(rr[k]) + sl[0].start, int(cc[k]) + sl[1].start)
        return True


def door_mouth(square: np.ndarray, width: float) -> np.ndarray:
    """The strip just inside a door (AABB): the cells the agent's centre crosses right
    after the opening, away from the jambs (and so from a leaf standing at a jamb)."""
    a, b, _, d = square
    u = (b - a) / np.hypot(*(b - a))
    side = (d - a) / np.hypot(*(d - a))
    inset = min(AGENT_RADIUS, width / 2 - 0.05)
    p0 = a + u * inset + side * AGENT_RADIUS
    p1 = b - u * inset + side * (AGENT_RADIUS + 0.25)
    return np.array([min(p0[0], p1[0]), min(p0[1], p1[1]), max(p0[0], p1[0]), max(p0[1], p1[1])])


def room_spaces(fp: FloorPlan, rng: np.random.Generator) -> list[RoomSpace]:
    """The furnisher's view of each room: inner outline, door squares, window zones."""
    spaces = []
    walls = {w.id: w for w in fp.walls}
    for i, poly in enumerate(fp.polygons):
        p = np.asarray(poly, dtype=np.float64)
        inner = inset_polygon(p, WALL_THICKNESS / 2)
        keep, leaves, mouths = [], [], []
        for door in fp.doors:
            if fp.room_ids[i] not in door.connects:
                continue
            if door.leaf and door_passable(door):
                hinge, tip = door_leaf_open_segment(walls[door.wall], door)
                if points_in_polygon(((hinge + tip) / 2)[None, :], p)[0]:
                    leaves.append((hinge, tip))
            for sq in door_keepout_squares(walls[door.wall], door):
                centre = sq.mean(axis=0)
                if points_in_polygon(centre[None, :], p)[0]:
                    keep.append(bounding_box(sq))
                    mouths.append(door_mouth(sq, door.width))
        wins = []
        for win in fp.windows:
            wall = walls[win.wall]
            if wall.rooms[0] != fp.room_ids[i]:
                continue
            s, u, n, _ = wall_frame(wall)  # outer walls have their room on the left
            lo, hi = opening_span(win)
            a = s + u * lo + n * (wall.thickness / 2)
            b = s + u * hi + n * (wall.thickness / 2 + WINDOW_DEPTH)
            wins.append([min(a[0], b[0]), min(a[1], b[1]), max(a[0], b[0]), max(a[1], b[1]), win.sill])
        space = RoomSpace(i, fp.types[i], inner, np.asarray(keep).reshape(-1, 4),
                          np.asarray(wins, dtype=np.float64).reshape(-1, 5), round(float(rng.uniform(0.1, 0.3)), 3),
                          leaves, np.asarray(mouths).reshape(-1, 4))
        space.reach = RoomReach(space)
        spaces.append(space)
    return spaces


# ---------------------------------------------------------------------------------------
# The furnisher


class Furnisher:
    """Places the furniture of one house attempt. ``pieces`` grows as pieces are accepted;
    an index into it is a piece's identity until ids are assigned."""

    def __init__(self, fp: FloorPlan, catalog: Catalog, rng: np.random.Generator,
                 caps: dict[str, int] | None = None):
        self.fp = fp
        self.catalog = catalog
        self.rng = rng
        self.spaces = room_spaces(fp, rng)
        self.pieces: list[Placed] = []
        self.caps = dict(caps or {})  # category -> how many more may be placed
        self._group = 0

    # -- choosing assets ----------------------------------------------------------------
    def available(self, category: str) -> bool:
        return category in self.catalog.by_category and self.caps.get(category, 1) > 0

    def pick(self, category: str) -> tuple[str, int, AssetModel]:
        ids = self.catalog.by_category[category]
        asset = ids[int(self.rng.integers(len(ids)))]
        variant = int(self.rng.integers(registry.GENERATED_VARIANTS))
        return asset, variant, registry.make(asset, variant)

    def count(self, category: str) -> int:
        return sum(p.category == category for p in self.pieces)

    # -- candidate poses ----------------------------------------------------------------
    def anchor_poses(self, space: RoomSpace, model: AssetModel, n_random: int = 6) -> np.ndarray:
        """Candidate poses (N, 4): x, y, quarter turns, preference. Poses of the asset's own
        ``placement`` come first (preference 10); wall poses are the fallback."""
        placement = model.placement if model.placement in ("wall", "corner", "middle") else "wall"
        local = local_footprint(model)
        edges = space.edges()
        s_min = WALL_GAP - local[0]
        fits = [k for k, edge in enumerate(edges) if not edge[3] - WALL_GAP - local[2] < s_min]
        parts = []
        if fits:
            s_max = np.array([edges[k][3] - WALL_GAP - local[2] for k in fits])
            # Every edge's random spots in one draw: the same numbers, edge after edge, as a
            # draw per edge (a generator fills an array in order, element by element).
            draws = self.rng.uniform(s_min, s_max[:, None], (len(fits), n_random))
            at_end, at_wall = (10.0 if placement == "corner" else 0.0), (10.0 if placement == "wall" else 0.0)
            along: list[float] = []
            edge_of: list[int] = []
            pref: list[float] = []
            for i, k in enumerate(fits):
                _, _, _, _, conv0, conv1 = edges[k]
                ends = [s for s, convex in ((s_min, conv0), (s_max[i], conv1)) if convex]
                spots = [*ends, 0.5 * (s_min + s_max[i]), *draws[i].tolist()]
                along += spots
                edge_of += [k] * len(spots)
                pref += [at_end] * len(ends) + [at_wall] * (len(spots) - len(ends))
            p0, e, n, q = space.edge_arrays()
            rows = np.array(edge_of)
            # All spots of all edges at once (the same arithmetic, element by element).
            o = p0[rows] + e[rows] * np.array(along, dtype=np.float64)[:, None] + n[rows] * (WALL_GAP - local[1])
            parts.append(np.column_stack([o, q[rows], pref]))
        if placement == "middle":
            bb = space.bbox
            pts = np.column_stack([self.rng.uniform(bb[0], bb[2], 40), self.rng.uniform(bb[1], bb[3], 40)])
            qs = self.rng.integers(0, 4, 40)
            parts.append(np.column_stack([pts, qs, np.full(40, 10.0)]))
        return np.concatenate(parts).astype(np.float64) if parts else np.zeros((0, 4))

    # -- checking -----------------------------------------------------------------------
    def valid(self, space: RoomSpace, rects: np.ndarray, fronts: np.ndarray, tall: np.ndarray) -> np.ndarray:
        """rects/fronts: (C, M, 4) per candidate and member; tall: (M,) member heights.
        Returns (C,) whether every member of the candidate group fits."""
        c, m = rects.shape[:2]
        flat = rects.reshape(-1, 4)
        fr = fronts.reshape(-1, 4)
        has_front = fr[:, 2] > fr[:, 0]
        # Footprints and front zones tested in one call (row by row the same test).
        inside = rects_in_polygon(np.concatenate([flat, np.where(has_front[:, None], fr, flat)]), space.inner)
        ok = inside[:len(flat)] & (~has_front | inside[len(flat):])
        others = [self.pieces[k] for k in space.pieces if self.pieces[k].on_floor]
        # What the footprints must stay clear of, tested in one call (pair by pair the same
        # test): the other pieces grown by the margin, their front zones, the door squares.
        clear_of = [space.keepouts]
        if others:
            feet = np.array([p.rect for p in others])
            ofronts = np.array([p.front for p in others if p.front is not None]).reshape(-1, 4)
            clear_of = [expand(feet, space.margin), ofronts, space.keepouts]
            ok &= ~(has_front & overlap_matrix(fr, feet).any(axis=1))
        ok &= ~overlap_matrix(flat, np.concatenate(clear_of)).any(axis=1)
        if len(space.windows):
            heights = np.tile(tall, c)
            hit = overlap_matrix(flat, space.windows[:, :4]) & (heights[:, None] > space.windows[None, :, 4] + WINDOW_TOLERANCE)
            ok &= ~hit.any(axis=1)
        # .all along an axis of a 2-D array gives an array (numpy's types allow a scalar)
        return cast(np.ndarray, ok.reshape(c, m).all(axis=1))

    # -- placing ------------------------------------------------------------------------
    def place(self, space: RoomSpace, category: str, *, group: str | None = None,
              required: bool = False, tries: int = 3) -> bool:
        """Place one piece (with its group) in a room; False if it does not fit."""
        if self.catalog.describe(category).placement == "hanging":
            return any(self.hang(space, category) for _ in range(tries))
        for _ in range(tries):
            asset, variant, model = self.pick(category)
            variants = self.group_variants(group, model, space.rtype) if group else [[]]
            poses = self.anchor_poses(space, model)
            if len(poses) == 0:
                continue
            for members in variants:
                if self._place_group(space, category, asset, variant, model, members, poses, group, required):
                    return True
        return False

    def _place_group(self, space, category, asset, variant, model, members, poses, group, required) -> bool:
        allm = [Member(category, asset, variant, model, 0.0, 0.0, 0)] + members
        xs, ys, qs, pref = poses[:, 0], poses[:, 1], poses[:, 2].astype(np.int64), poses[:, 3]
        rects, fronts = self._member_rects(allm, xs, ys, qs)
        tall = np.array([m.model.size[2] for m in allm])
        ok = self.valid(space, rects, fronts, tall)
        if not ok.any():
            return False
        order = self._rank(space, model, rects[:, 0], qs, pref, ok)
        for c in order[:4]:
            placed = self._commit(space, allm, xs[c], ys[c], int(qs[c]), rects[c], fronts[c], required)
            if self._room_ok(space):
                if group == "tv":
                    self.put_on_support(placed[0], "tv")
                return True
            self._rollback(space, len(placed))
        return False

    def hang(self, space: RoomSpace, category: str) -> bool:
        """Hang one piece (a picture) on a free stretch of the room's walls: clear of
        windows, doors, open door leaves and other hung pieces, at eye level or higher
        above the furniture in front of it, below the ceiling. It blocks no floor, so the
        room's reach check does not see it. False if no stretch has room."""
        asset, variant, model = self.pick(category)
        local = local_footprint(model)
        height = float(model.size[2])
        edges = space.edges()
        p0, e, n, q = space.edge_arrays()
        s_min = HANG_APART - local[0]
        fits = [k for k, edge in enumerate(edges) if edge[3] - HANG_APART - local[2] > s_min]
        if not fits:
            return False
        along = self.rng.uniform(s_min, np.array([edges[k][3] - HANG_APART - local[2] for k in fits])[:, None],
                                 (len(fits), 4)).reshape(-1)
        rows = np.repeat(np.array(fits), 4)
        # The back 5 mm off the wall face (the inner outline).
        o = p0[rows] + e[rows] * along[:, None] + n[rows] * (0.005 - local[1])
        qs = q[rows].astype(np.int64)
        rects = self._member_rects([Member(category, asset, variant, model, 0.0, 0.0, 0)], o[:, 0], o[:, 1], qs)[0][:, 0]
        apart = expand(rects, HANG_APART)
        keep = rects_in_polygon(rects, space.inner)
        blocked = [space.keepouts, space.windows[:, :4].reshape(-1, 4)]
        blocked += [np.array([[min(h[0], t[0]), min(h[1], t[1]), max(h[0], t[0]), max(h[1], t[1])]])
                    for h, t in space.leaves]
        hung = [self.pieces[k] for k in space.pieces if self.pieces[k].hanging]
        if hung:
            blocked.append(np.array([p.rect for p in hung]))
        keep &= ~overlap_matrix(apart, np.concatenate(blocked)).any(axis=1)
        ceiling = max((w.height for w in self.fp.walls), default=3.0)
        floor_pieces = [self.pieces[k] for k in space.pieces if self.pieces[k].on_floor]
        under = np.zeros(len(rects))
        if floor_pieces:
            # What stands in front of the stretch of wall (its footprint reaching within 10 cm
            # of the wall): the picture hangs above the tallest of it.
            near = overlap_matrix(expand(rects, 0.1), np.array([p.rect for p in floor_pieces]))
            tops = np.array([p.z + p.height for p in floor_pieces])
            under = np.where(near, tops[None, :], 0.0).max(axis=1)
        bottom = np.maximum(HANG_CENTRE - height / 2, under + HANG_ABOVE_FURNITURE)
        keep &= bottom + height <= ceiling - HANG_BELOW_CEILING
        idx = np.flatnonzero(keep)
        if len(idx) == 0:
            return False
        c = int(idx[int(self.rng.integers(len(idx)))])
        self._group += 1
        self.pieces.append(Placed(category, asset, variant, float(o[c, 0]), float(o[c, 1]), int(qs[c]), model,
                                  space.index, self._group, rects[c].copy(), None, z=round(float(bottom[c]), 4)))
        space.pieces.append(len(self.pieces) - 1)
        if category in self.caps:
            self.caps[category] -= 1
        return True

    # -- single pieces, for other placers (the plan solver) -----------------------------
    def footprints(self, category: str, asset: str, variant: int, model: AssetModel, xs: np.ndarray,
                   ys: np.ndarray, qs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Footprints and front zones (C, 1, 4) of one piece at candidate poses."""
        return self._member_rects([Member(category, asset, variant, model, 0.0, 0.0, 0)], xs, ys, qs)

    def add_piece(self, space: RoomSpace, category: str, asset: str, variant: int, model: AssetModel,
                  x: float, y: float, q: int, rect: np.ndarray, front: np.ndarray) -> int:
        """Commit one piece on the floor (checked by :meth:`valid`); its index in ``pieces``."""
        return self._commit(space, [Member(category, asset, variant, model, 0.0, 0.0, 0)], x, y, q,
                            rect[None, :], front[None, :], False)[0]

    def remove_last(self, space: RoomSpace, n: int = 1) -> None:
        """Take back the last ``n`` pieces of ``space`` (the last ones placed)."""
        self._rollback(space, n)

    def room_ok(self, space: RoomSpace) -> bool:
        """Whether the agent still walks between the room's doors and reaches every piece."""
        return self._room_ok(space)

    def _member_rects(self, members: list[Member], xs, ys, qs):
        c = len(xs)
        rects = np.zeros((c, len(members), 4))
        fronts = np.zeros((c, len(members), 4))
        turns = qs % 4
        for j, m in enumerate(members):
            # The member's offset turned by each of the four quarter turns (row by row the
            # arithmetic of turning it by each candidate's), picked per candidate.
            off = np.einsum("cij,j->ci", QUARTER_TURNS, np.array([m.dx, m.dy]))[turns]
            ox, oy = xs + off[:, 0], ys + off[:, 1]
            mq = (qs + m.dq) % 4
            fz = float(m.model.front_clearance)
            table, ftable = m.model.derived(("turned footprints", fz), _turned_footprints)
            base = np.column_stack([ox, oy, ox, oy])
            rects[:, j] = base + table[mq]
            fronts[:, j] = base + ftable[mq] if fz > 0 else 0.0
        return rects, fronts

    def _rank(self, space: RoomSpace, model: AssetModel, rects: np.ndarray, qs: np.ndarray, pref: np.ndarray,
              ok: np.ndarray) -> list[int]:
        """Valid candidates, best first: the asset's own placement kind before the
        fallback, then at random, except that middle pieces prefer open floor and a tv
        stand prefers to face the sofa."""
        score = self.rng.random(len(qs)) + pref
        if model.placement == "middle":
            score += 4.0 * self._openness(space, rects)
        if model.category == "tv_stand":
            sofas = [self.pieces[k] for k in space.pieces if self.pieces[k].category == "sofa"]
            if sofas:
                s = sofas[0]
                facing = qs == (s.q + 2) % 4
                cx = (rects[:, 0] + rects[:, 2]) / 2 - (s.rect[0] + s.rect[2]) / 2
                cy = (rects[:, 1] + rects[:, 3]) / 2 - (s.rect[1] + s.rect[3]) / 2
                lateral = np.where(s.q % 2 == 0, np.abs(cx), np.abs(cy))
                score += 3.0 * facing - lateral
        idx = np.nonzero(ok)[0]
        return idx[np.argsort(-score[idx], kind="stable")].tolist()

    def _openness(self, space: RoomSpace, rects: np.ndarray) -> np.ndarray:
        """Distance (capped at 1.5 m) from each rectangle to the nearest wall or piece."""
        bb = space.bbox
        d = np.minimum.reduce([rects[:, 0] - bb[0], rects[:, 1] - bb[1], bb[2] - rects[:, 2], bb[3] - rects[:, 3]])
        for k in space.pieces:
            r = self.pieces[k].rect
            gx = np.maximum(np.maximum(r[0] - rects[:, 2], rects[:, 0] - r[2]), 0.0)
            gy = np.maximum(np.maximum(r[1] - rects[:, 3], rects[:, 1] - r[3]), 0.0)
            d = np.minimum(d, np.hypot(gx, gy))
        return np.minimum(d, 1.5)

    def _commit(self, space, members, x, y, q, rects, fronts, required) -> list[int]:
        self._group += 1
        out = []
        for j, m in enumerate(members):
            off = QUARTER_TURNS[q] @ np.array([m.dx, m.dy])
            fz = m.model.front_clearance
            piece = Placed(m.category, m.asset, m.variant, float(x + off[0]), float(y + off[1]), (q + m.dq) % 4,
                           m.model, space.index, self._group, rects[j].copy(),
                           fronts[j].copy() if fz > 0 else None, required=required and j == 0)
            self.pieces.append(piece)
            space.pieces.append(len(self.pieces) - 1)
            space.reach.add(piece.rect)
            if m.category in self.caps:
                self.caps[m.category] -= 1
            out.append(len(self.pieces) - 1)
        return out

    def _rollback(self, space: RoomSpace, n: int) -> None:
        for _ in range(n):
            piece = self.pieces.pop()
            space.pieces.pop()
            if piece.category in self.caps:
                self.caps[piece.category] += 1
        reach = space.require_reach()
        reach.clear()
        for k in space.pieces:
            if self.pieces[k].on_floor:
                reach.add(self.pieces[k].rect)

    def _room_ok(self, space: RoomSpace) -> bool:
        targets = [self.pieces[k].rect for k in space.pieces if self.pieces[k].on_floor]
        return space.require_reach().ok(targets)

    # -- groups -------------------------------------------------------------------------
    def group_variants(self, group: str, anchor: AssetModel, rtype: str = "") -> list[list[Member]]:
        """Member layouts for a group in a room of type ``rtype``, fullest first (the last
        one is the anchor alone)."""
        a = local_footprint(anchor)
        if group == "desk":
            variants = self._desk(a, rtype)
        else:
            build = {"bed": self._bed, "sofa": self._sofa, "dining": self._dining}.get(group)
            variants = build(a) if build else []
        variants = [v for v in variants if self._within_caps(v)]
        return variants + [[]]

    def _within_caps(self, members: list[Member]) -> bool:
        need: dict[str, int] = {}
        for m in members:
            need[m.category] = need.get(m.category, 0) + 1
        return all(self.caps.get(c, n) >= n for c, n in need.items())

    def _bed(self, a: np.ndarray) -> list[list[Member]]:
        if not self.available("nightstand"):
            return []
        asset, variant, model = self.pick("nightstand")
        m = local_footprint(model)
        y = a[1] - m[1]  # backs aligned at the wall
        left = Member("nightstand", asset, variant, model, a[0] - GROUP_GAP - m[2], y, 0)
        right = Member("nightstand", asset, variant, model, a[2] + GROUP_GAP - m[0], y, 0)
        return [[left, right], [right], [left]]

    def _sofa(self, a: np.ndarray) -> list[list[Member]]:
        if not self.available("coffee_table") or self.rng.random() > 0.85:
            return []
        asset, variant, model = self.pick("coffee_table")
        m = local_footprint(model)
        gap = float(self.rng.uniform(0.4, 0.5))
        return [[Member("coffee_table", asset, variant, model, -(m[0] + m[2]) / 2, a[3] + gap - m[1], 0)]]

    def _desk(self, a: np.ndarray, rtype: str) -> list[list[Member]]:
        """The desk's chair: an office chair in most offices, else a plain one."""
        office = self.available("office_chair") and self.rng.random() < OFFICE_CHAIR_P.get(rtype, OFFICE_CHAIR_P_ELSEWHERE)
        category = "office_chair" if office else "chair"
        if not self.available(category):
            return []
        asset, variant, model = self.pick(category)
        m = local_footprint(model)
        # Turned half a turn: the chair's front faces the desk.
        return [[Member(category, asset, variant, model, (m[0] + m[2]) / 2, a[3] + GROUP_GAP + m[3], 2)]]

    def _dining(self, a: np.ndarray) -> list[list[Member]]:
        """Chairs along the table's long sides (and sometimes its ends), facing it."""
        if not self.available("chair"):
            return []
        asset, variant, model = self.pick("chair")
        m = local_footprint(model)
        cw = m[2] - m[0]
        long_x = (a[2] - a[0]) >= (a[3] - a[1])
        side_len = (a[2] - a[0]) if long_x else (a[3] - a[1])
        n_side = int(max(1, min(3, (side_len + 0.1) // (cw + 0.15))))

        def chair(side: int, t: float) -> Member:
            # side: 0 +y, 1 -x, 2 -y, 3 +x in the table frame; the chair faces the table.
            cx = -(m[0] + m[2]) / 2  # centre the chair's width on its slot
            depth = GROUP_GAP + m[3]
            if side == 0:
                return Member("chair", asset, variant, model, t - cx, a[3] + depth, 2)
            if side == 2:
                return Member("chair", asset, variant, model, t + cx, a[1] - depth, 0)
            if side == 1:
                return Member("chair", asset, variant, model, a[0] - depth, t - cx, 3)
            return Member("chair", asset, variant, model, a[2] + depth, t + cx, 1)

        def row(side: int, n: int) -> list[Member]:
            lo, hi = (a[0], a[2]) if side in (0, 2) else (a[1], a[3])
            slots = [lo + (hi - lo) * (k + 0.5) / n for k in range(n)]
            return [chair(side, t) for t in slots]

        sides = (0, 2) if long_x else (1, 3)
        ends = (1, 3) if long_x else (0, 2)
        full = row(sides[0], n_side) + row(sides[1], n_side)
        variants = []
        if side_len > 1.3 and self.rng.random() < 0.5:
            variants.append(full + row(ends[0], 1) + row(ends[1], 1))
        variants.append(full)
        if n_side > 1:
            variants.append(row(sides[0], 1) + row(sides[1], 1))
        variants.append(row(sides[0], 1))
        return variants

    def place_anywhere(self, category: str) -> bool:
        """One more piece of ``category`` in any room that allows it (a surface piece goes
        on a free support, or on a new one)."""
        if category in SUPPORTS:
            for k in range(len(self.pieces)):
                p = self.pieces[k]
                taken = any(q.support == k for q in self.pieces)
                if p.category in SUPPORTS[category] and not taken and self.put_on_support(k, category):
                    return True
            supports = [c for c in SUPPORTS[category] if self.available(c)]
            for support in supports:
                before = self.count(category)
                if self.place_anywhere(support) and (
                        self.count(category) > before or self.put_on_support(len(self.pieces) - 1, category)):
                    return True
            return False
        types = allowed_room_types(self.catalog, category)
        spaces = [s for s in self.spaces if s.rtype in types]
        for k in self.rng.permutation(len(spaces)).tolist():
            if self.place(spaces[k], category, group=DEFAULT_GROUP.get(category), tries=4):
                return True
        return False

    # -- surface furniture (a tv on its stand) --------------------------------------------
    def put_on_free_support(self, space: RoomSpace, category: str) -> bool:
        """Stand a surface piece on a piece of this room that may hold it (see SUPPORTS)
        and holds nothing yet; False if none does or it fits on none."""
        for k in space.pieces:
            p = self.pieces[k]
            if (p.category in SUPPORTS.get(category, ()) and p.on_floor
                    and not any(q.support == k for q in self.pieces) and self.put_on_support(k, category)):
                return True
        return False

    def put_on_support(self, support: int, category: str, tries: int = 3) -> bool:
        """Stand a surface piece (a tv) on the top receptacle of piece ``support``."""
        if not self.available(category):
            return False
        base = self.pieces[support]
        recs = [(k, r) for k, r in enumerate(base.model.receptacles) if r.link == "base"]
        if not recs:
            return False
        k, rec = max(recs, key=lambda kr: (kr[1].height, kr[0]))
        for _ in range(tries):
            asset, variant, model = self.pick(category)
            local = local_footprint(model)
            if model.size[2] > rec.clearance + EPS:
                continue
            pos = fit_centered(rec, local)
            if pos is None:
                continue
            off = QUARTER_TURNS[base.q] @ pos
            rect = np.array([base.x + off[0], base.y + off[1]] * 2) + turned_rect(local, base.q)
            space = self.spaces[base.room]
            piece = Placed(category, asset, variant, float(base.x + off[0]), float(base.y + off[1]), base.q, model,
                           base.room, base.group, rect, None, z=base.z + rec.height, support=support, receptacle=k)
            self.pieces.append(piece)
            space.pieces.append(len(self.pieces) - 1)
            if category in self.caps:
                self.caps[category] -= 1
            return True
        return False


def _turned_footprints(model: AssetModel) -> tuple[np.ndarray, np.ndarray]:
    """(4, 4) footprint boxes of a model and of its front clearance zone, turned by 0..3
    quarter turns (made once per model: every placement tries them all)."""
    local = local_footprint(model)
    fz = float(model.front_clearance)
    table = np.array([turned_rect(local, k) for k in range(4)])
    ftable = np.array([turned_rect(np.array([local[0], local[3], local[2], local[3] + fz]), k) for k in range(4)])
    for a in (table, ftable):
        a.flags.writeable = False
    return table, ftable


def fit_centered(rec: Receptacle, local: np.ndarray) -> np.ndarray | None:
    """Where to put an object's origin so its footprint is centred on a receptacle and
    backed toward its rear edge; None if it does not fit."""
    half = np.asarray(rec.half_size)
    size = np.array([local[2] - local[0], local[3] - local[1]])
    if (size > 2 * half + 1e-9).any():
        return None
    cx = rec.center[0] - (local[0] + local[2]) / 2
    y_back = rec.center[1] - half[1] - local[1]
    y_centre = rec.center[1] - (local[1] + local[3]) / 2
    return np.array([cx, (y_back + y_centre) / 2])


# ---------------------------------------------------------------------------------------
# A whole house


def room_label(fp: FloorPlan, i: int) -> str:
    return ROOM_TYPES[fp.types[i]].name


def extra_rules(catalog: Catalog, rtype: str) -> list[Rule]:
    """Optional rules for registered furniture categories the tables do not mention but
    whose ``rooms`` annotation names this room type (user assets join in)."""
    key = ("extra rules", rtype)
    rules = catalog.memo.get(key)
    if rules is None:
        rules = catalog.memo[key] = tuple(_extra_rules(catalog, rtype))
    return list(cast(tuple[Rule, ...], rules))


def _extra_rules(catalog: Catalog, rtype: str) -> list[Rule]:
    known = {r.category for prio, opt in ROOM_FURNITURE.values() for r in prio + opt}
    known |= {c for members in GROUP_MEMBERS.values() for c in members}
    out = []
    for cat in catalog.categories:
        if cat in known or not catalog.is_furniture(cat):
            continue
        model = catalog.describe(cat)
        if model.placement not in ("surface", "hanging", "floor") and rtype in model.rooms:
            out.append(Rule(cat, EXTRA_CATEGORY_P))
    return out


def furnish_house(fp: FloorPlan, catalog: Catalog, rng: np.random.Generator, *,
                  need: dict[str, int] | None = None, caps: dict[str, int] | None = None) -> Furnisher:
    """Furnish every room: priority pieces, then what ``need`` asks for (category ->
    at least this many), then optional pieces. ``caps`` bounds categories (exact counts).

    Raises :class:`PlacementFailed` when a priority or needed piece does not fit."""
    f = Furnisher(fp, catalog, rng, caps)
    for space in f.spaces:
        for rule in ROOM_FURNITURE.get(space.rtype, ([], []))[0]:
            if f.available(rule.category) and not f.place(space, rule.category, group=rule.group,
                                                          required=True, tries=4):
                raise PlacementFailed(f"no room for a {rule.category} in the {room_label(fp, space.index)}")
    wanted = need or {}
    for cat in sorted(wanted):
        while f.count(cat) < wanted[cat]:
            if not f.place_anywhere(cat):
                raise PlacementFailed(f"placed {f.count(cat)} of {wanted[cat]}: no more room for a {cat}", cat)
    for space in f.spaces:
        rules = ROOM_FURNITURE.get(space.rtype, ([], []))[1] + extra_rules(catalog, space.rtype)
        for rule in rules:
            if not f.available(rule.category) or rng.random() >= rule.p:
                continue
            for _ in range(int(rng.integers(rule.count[0], rule.count[1] + 1))):
                if f.available(rule.category):
                    f.place(space, rule.category, group=rule.group, tries=1 if rule.p < 0.5 else 2)
    for space in f.spaces:
        for rule in ROOM_SURFACE_PIECES.get(space.rtype, []):
            if f.available(rule.category) and rng.random() < rule.p:
                f.put_on_free_support(space, rule.category)
    if f.available("wall_picture"):
        for space in f.spaces:
            p, (lo, hi) = WALL_DECOR.get(space.rtype, (0.0, (0, 0)))
            if rng.random() < p:
                for _ in range(int(rng.integers(lo, hi + 1))):
                    if f.available("wall_picture"):
                        f.hang(space, "wall_picture")
    return f
