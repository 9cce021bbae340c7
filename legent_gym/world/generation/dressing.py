"""Set dressing: what a furnished house gets before its small objects, each thing where it
belongs to a piece already there.

* **Wall cabinets** over the counters, sinks and dishwashers that stand against a kitchen's
  walls, one run per kitchen in one style (one variant, stretched to each piece's width),
  and a **hood** over the stove; none in front of a window or over a hung picture.
* **Rugs** under a living room's coffee table, a dining table (with its chairs) and the
  foot of a bed, stretched to what they lie under and kept inside the room.
* **Mats** in front of a bathtub and along a kitchen counter (the rug asset, stretched).
* **Curtains** each side of a window, a room's all alike, hanging from above the window to
  below its sill, where no furniture, door or picture is in the way.
* **Cushions** against the back of sofas and armchairs.
* **Rows of books** on the open shelves of bookshelves (and some tv stands, coffee tables
  and console tables) the agent can reach: upright, spines to the front, from one end of
  the shelf, so small objects still find room beside them.

The assets are :mod:`legent_gym.world.assets.library.fittings`'. Every piece is a
:class:`~legent_gym.world.generation.furnish.Placed` appended to the furnisher's pieces
(books rest on their shelf: ``support`` and ``receptacle``), so the small objects that
follow keep clear of the books, and the scene gets them after the furniture.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.assets.model import AssetModel, Receptacle
from legent_gym.world.generation.furnish import Furnisher, Placed, RoomSpace
from legent_gym.world.generation.small_objects import open_receptacle, receptacle_corners
from legent_gym.world.geometry import (
    HANGING_HEIGHT,
    QUARTER_TURNS,
    expand,
    local_footprint,
    opening_span,
    overlap_matrix,
    points_in_polygon,
    quarter_turns_facing,
    rects_in_polygon,
    turned_rect,
    wall_frame,
)

#: Furniture whose open shelves (receptacles below its top) may hold a row of books, with
#: the probability that one shelf does.
BOOK_SHELVES = {"bookshelf": 0.9, "tv_stand": 0.5, "coffee_table": 0.4, "console_table": 0.5, "bench": 0.2}
#: The share of a shelf's width a row of books takes, and the fewest books a row has.
ROW_FILL = (0.55, 0.95)
ROW_MIN = 3
#: Gap between two books of a row, and between a row and the shelf's ends (metres).
BOOK_GAP = 0.002
SHELF_MARGIN = 0.01
#: Variants a shelved book is drawn from: more than other types' (a shelf holds dozens,
#: which should rarely repeat), and small (five boxes each).
BOOK_VARIANTS = 512

#: Kitchen pieces a wall cabinet hangs over, and the one a hood hangs over.
UNDER_CABINETS = ("kitchen_counter", "sink", "dishwasher")
UNDER_HOOD = "stove"
#: The probability that a kitchen has wall cabinets (and a hood over its stove).
P_WALL_CABINETS = 0.85
#: A wall cabinet's underside above the floor, and a hood's above the cooktop (metres).
CABINET_BOTTOM = 1.45
HOOD_ABOVE_COOKTOP = 0.65
#: Least gap between a hanging piece's top and the ceiling.
BELOW_CEILING = 0.05
#: A piece this wide or wider gets two wall cabinets over it.
TWO_CABINETS_FROM = 1.2
#: How far behind a piece's back the wall must be for it to count as standing against it.
AGAINST_WALL = 0.06

#: Per room type: the probability of a rug, and the piece it lies under with its margins
#: (metres beyond the piece's footprint across and along its depth, negative: shorter).
RUGS: dict[str, tuple[float, str, tuple[float, float]]] = {
    "living_room": (0.75, "coffee_table", (0.5, 0.45)),
    "dining_room": (0.6, "dining_table", (0.65, 0.65)),
    "bedroom": (0.7, "bed", (0.45, -0.6)),
    "office": (0.35, "desk", (0.3, 0.6)),
}
#: Per room type: the probability of a mat in front of a piece, the piece, and the mat's
#: size (share of the piece's width, depth in metres).
MATS: dict[str, tuple[float, tuple[str, ...], tuple[float, float]]] = {
    "bathroom": (0.7, ("bathtub", "shower", "sink", "vanity"), (0.8, 0.5)),
    "kitchen": (0.4, ("kitchen_counter", "sink"), (0.9, 0.6)),
}
#: The probability that a room with windows has curtains; a panel's share of its width that
#: covers the window, and how far the curtain reaches above the window and below its sill.
P_CURTAINS = 0.7
CURTAIN_OVER_WINDOW = 0.25
CURTAIN_ABOVE, CURTAIN_BELOW = 0.12, 0.15
#: Seats that get cushions: (probability, fewest, most).
CUSHIONS = {"sofa": (0.85, 2, 4), "armchair": (0.5, 1, 1), "bed": (0.5, 2, 3)}
#: Per room type: where its rug goes when what it lies under is missing: in front of the
#: first of these pieces (a living room's sofa), and its size (as :data:`MATS`').
RUG_IN_FRONT: dict[str, tuple[tuple[str, ...], tuple[float, float]]] = {
    "living_room": (("sofa", "armchair"), (1.0, 1.3)),
}
#: A rug is shrunk this much per try when it does not fit the room, at most this many times.
RUG_SHRINK, RUG_TRIES = 0.85, 3
#: Least gap between a rug and the walls, and its smallest sides.
RUG_WALL_GAP = 0.08
RUG_MIN = (0.9, 0.6)


def dress_house(f: Furnisher, rng: np.random.Generator, can_reach: Callable[[np.ndarray], bool]) -> int:
    """Dress every room of a furnished house; the number of pieces added to ``f.pieces``.
    ``can_reach`` tells whether the agent can reach a rectangle (world corners (4, 2)) from
    where it walks: what hangs on walls and the shelves that get books must pass it."""
    before = len(f.pieces)
    for space in f.spaces:
        if space.rtype == "kitchen" and rng.random() < P_WALL_CABINETS:
            hang_kitchen_run(f, space, rng, can_reach)
        rug = RUGS.get(space.rtype)
        if rug is not None and rng.random() < rug[0] and not lay_rug(f, space, rng, rug[1], rug[2]) \
                and space.rtype in RUG_IN_FRONT:
            lay_mat(f, space, rng, *RUG_IN_FRONT[space.rtype])
        mat = MATS.get(space.rtype)
        if mat is not None and rng.random() < mat[0]:
            lay_mat(f, space, rng, mat[1], mat[2])
        if len(space.windows) and rng.random() < P_CURTAINS:
            hang_curtains(f, space, rng, can_reach)
    place_cushions(f, rng)
    shelve_books(f, rng, can_reach)
    return len(f.pieces) - before


# ---------------------------------------------------------------------------------------
# Pieces


def _add(f: Furnisher, space: RoomSpace, piece: Placed) -> None:
    f.pieces.append(piece)
    space.pieces.append(len(f.pieces) - 1)


def _world_rect(x: float, y: float, q: int, local: np.ndarray) -> np.ndarray:
    return np.array([x, y, x, y]) + turned_rect(local, q)


def _reach_corners(rect: np.ndarray) -> np.ndarray:
    """The corners of a footprint drawn in by a centimetre: what is within reach of them is
    within reach of the footprint however the scene rounds its position."""
    x0, y0, x1, y1 = (float(v) for v in expand(rect, -0.01))
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])


def _scaled_local(model: AssetModel, sx: float, sy: float) -> np.ndarray:
    return local_footprint(model) * np.array([sx, sy, sx, sy])


# ---------------------------------------------------------------------------------------
# Kitchens


def _against_wall(space: RoomSpace, piece: Placed) -> bool:
    """Whether the piece's back stands at a wall: just behind its back is outside the room."""
    lo = local_footprint(piece.model)
    behind = np.array([[(lo[0] + lo[2]) / 2 + dx, lo[1] - AGAINST_WALL] for dx in (-0.2, 0.0, 0.2)])
    pts = behind @ QUARTER_TURNS[piece.q].T + np.array([piece.x, piece.y])
    return not points_in_polygon(pts, space.inner).any()


def hang_kitchen_run(f: Furnisher, space: RoomSpace, rng: np.random.Generator,
                     can_reach: Callable[[np.ndarray], bool]) -> int:
    """Wall cabinets over the kitchen's base pieces against a wall (one variant), and a hood
    over its stove; the number hung."""
    ceiling = max((w.height for w in f.fp.walls), default=3.0)
    bases = [k for k in space.pieces if f.pieces[k].on_floor and f.pieces[k].category in (*UNDER_CABINETS, UNDER_HOOD)
             and f.pieces[k].yaw is None and _against_wall(space, f.pieces[k])]
    if not bases:
        return 0
    cabinet_variant = int(rng.integers(registry.GENERATED_VARIANTS))
    cabinet = registry.make("wall_cabinet", cabinet_variant)
    hood_variant = int(rng.integers(registry.GENERATED_VARIANTS))
    hung = 0
    for k in bases:
        base = f.pieces[k]
        lo = local_footprint(base.model)
        width = float(lo[2] - lo[0])
        if base.category == UNDER_HOOD:
            model, variant = registry.make("range_hood", hood_variant), hood_variant
            bottom = base.z + base.height + HOOD_ABOVE_COOKTOP
            modules = 1
        else:
            model, variant = cabinet, cabinet_variant
            bottom = max(CABINET_BOTTOM, base.z + base.height + 0.45)
            modules = 2 if width >= TWO_CABINETS_FROM else 1
        if bottom + float(model.size[2]) > ceiling - BELOW_CEILING:
            continue
        m_lo = local_footprint(model)
        sx = width / modules / float(m_lo[2] - m_lo[0])
        for j in range(modules):
            # The module's centre along the base's width, its back on the base's back.
            cx = (lo[0] + lo[2]) / 2 + (j + 0.5 - modules / 2) * width / modules
            cy = lo[1] - m_lo[1]
            off = QUARTER_TURNS[base.q] @ np.array([cx, cy])
            x, y = base.x + float(off[0]), base.y + float(off[1])
            rect = _world_rect(x, y, base.q, _scaled_local(model, sx, 1.0))
            if not _wall_free(f, space, rect) or not can_reach(_reach_corners(rect)):
                continue
            _add(f, space, Placed(model.category, model.asset_id, variant, x, y, base.q, model, space.index,
                                  base.group, rect, None, z=round(bottom, 4), scale=(round(sx, 4), 1.0, 1.0)))
            hung += 1
    return hung


def _wall_free(f: Furnisher, space: RoomSpace, rect: np.ndarray, *, windows: bool = True) -> bool:
    """No window behind a hanging piece's stretch of wall (unless ``windows`` is false), and
    nothing hung there yet."""
    if windows and len(space.windows) and overlap_matrix(rect[None, :], space.windows[:, :4]).any():
        return False
    hung = [f.pieces[k].rect for k in space.pieces if f.pieces[k].hanging]
    return not (hung and overlap_matrix(rect[None, :], np.array(hung)).any())


# ---------------------------------------------------------------------------------------
# Rugs


def _first_on_floor(f: Furnisher, space: RoomSpace, categories: tuple[str, ...]) -> Placed | None:
    """The room's first axis-aligned floor piece of the first of ``categories`` it has."""
    for category in categories:
        for k in space.pieces:
            p = f.pieces[k]
            if p.category == category and p.on_floor and p.yaw is None:
                return p
    return None


def lay_rug(f: Furnisher, space: RoomSpace, rng: np.random.Generator, under: str,
            margins: tuple[float, float]) -> bool:
    """A rug centred under the room's first piece of category ``under``, its footprint plus
    ``margins``, shrunk until it fits the room; False if there is no such piece or no fit."""
    base = _first_on_floor(f, space, (under,))
    if base is None:
        return False
    lo = local_footprint(base.model)
    want = np.array([lo[2] - lo[0] + 2 * margins[0], lo[3] - lo[1] + 2 * margins[1]])
    # The centre: the piece's, moved toward its front by half the change in depth (a bed's
    # rug lies under its foot end).
    centre = np.array([(lo[0] + lo[2]) / 2, (lo[1] + lo[3]) / 2 + max(0.0, -margins[1])])
    variant = int(rng.integers(registry.GENERATED_VARIANTS))
    model = registry.make("rug", variant)
    size = model.size
    inner = space.inner
    # Kept off the walls of the room's bounding box (a bed's rug runs short on the wall
    # side), then shrunk about its centre until it lies inside the room (an L's inner corner).
    off = QUARTER_TURNS[base.q] @ centre
    half = np.abs(QUARTER_TURNS[base.q]) @ (want / 2)  # world half extents
    bb = expand(space.bbox, -RUG_WALL_GAP)
    c = np.array([base.x, base.y]) + off
    rect = np.clip(np.concatenate([c - half, c + half]), bb[[0, 1, 0, 1]], bb[[2, 3, 2, 3]])
    for _ in range(RUG_TRIES + 1):
        world = rect[2:] - rect[:2]
        local = np.abs(QUARTER_TURNS[base.q]).T @ world  # back to the piece's axes
        if (local < np.asarray(RUG_MIN)).any():
            return False
        grown = expand(rect, RUG_WALL_GAP)
        if rects_in_polygon(grown[None, :], inner)[0]:
            x, y = float((rect[0] + rect[2]) / 2), float((rect[1] + rect[3]) / 2)
            sx, sy = float(local[0] / size[0]), float(local[1] / size[1])
            _add(f, space, Placed("rug", "rug", variant, x, y, base.q, model, space.index, base.group, rect, None,
                                  scale=(round(sx, 4), round(sy, 4), 1.0)))
            return True
        mid = (rect[:2] + rect[2:]) / 2
        rect = np.concatenate([mid - world * RUG_SHRINK / 2, mid + world * RUG_SHRINK / 2])
    return False


def lay_mat(f: Furnisher, space: RoomSpace, rng: np.random.Generator, before: tuple[str, ...],
            size: tuple[float, float]) -> bool:
    """A mat on the floor in front of the room's first piece of the first category of
    ``before`` it has (a bath mat, a kitchen runner), inside the room; False if there is none
    or no fit."""
    base = _first_on_floor(f, space, before)
    if base is None:
        return False
    lo = local_footprint(base.model)
    want = np.array([min((lo[2] - lo[0]) * size[0], 1.6), size[1]])
    centre = np.array([(lo[0] + lo[2]) / 2, lo[3] + 0.03 + size[1] / 2])
    variant = int(rng.integers(registry.GENERATED_VARIANTS))
    model = registry.make("rug", variant)
    sx, sy = float(want[0] / model.size[0]), float(want[1] / model.size[1])
    off = QUARTER_TURNS[base.q] @ centre
    x, y = base.x + float(off[0]), base.y + float(off[1])
    rect = _world_rect(x, y, base.q, _scaled_local(model, sx, sy))
    grown = expand(rect, RUG_WALL_GAP)
    if not rects_in_polygon(grown[None, :], space.inner)[0]:
        return False
    _add(f, space, Placed("rug", "rug", variant, x, y, base.q, model, space.index, base.group, rect, None,
                          scale=(round(sx, 4), round(sy, 4), 1.0)))
    return True


# ---------------------------------------------------------------------------------------
# Curtains


def hang_curtains(f: Furnisher, space: RoomSpace, rng: np.random.Generator,
                  can_reach: Callable[[np.ndarray], bool]) -> int:
    """A curtain each side of every window of the room (one variant), where it is clear of
    doors, door leaves, hung pieces and any furniture reaching above its hem; the number hung."""
    walls = {w.id: w for w in f.fp.walls}
    ceiling = max((w.height for w in f.fp.walls), default=3.0)
    variant = int(rng.integers(registry.GENERATED_VARIANTS))
    model = registry.make("curtain", variant)
    m_lo = local_footprint(model)
    width = float(m_lo[2] - m_lo[0])
    blocked = [space.keepouts]
    blocked += [np.array([[min(h[0], t[0]), min(h[1], t[1]), max(h[0], t[0]), max(h[1], t[1])]])
                for h, t in space.leaves]
    hung = 0
    for win in f.fp.windows:
        wall = walls[win.wall]
        if wall.rooms[0] != f.fp.room_ids[space.index]:
            continue
        s, u, n, _ = wall_frame(wall)  # outer walls have their room on the left
        q = quarter_turns_facing((float(n[0]), float(n[1])))
        top = min(win.sill + win.height + CURTAIN_ABOVE, ceiling - BELOW_CEILING)
        bottom = max(win.sill - CURTAIN_BELOW, HANGING_HEIGHT)
        sz = (top - bottom) / float(model.size[2])
        lo, hi = opening_span(win)
        cover = width * CURTAIN_OVER_WINDOW
        for along in (lo - width / 2 + cover, hi + width / 2 - cover):
            # The back 5 mm off the wall's face.
            o = s + u * along + n * (wall.thickness / 2 + 0.005 - float(m_lo[1]))
            x, y = float(o[0]), float(o[1])
            rect = _world_rect(x, y, q, m_lo)
            if not rects_in_polygon(rect[None, :], space.inner)[0]:
                continue
            if overlap_matrix(rect[None, :], np.concatenate(blocked).reshape(-1, 4)).any():
                continue
            if not _wall_free(f, space, rect, windows=False):
                continue
            under = [f.pieces[k] for k in space.pieces if f.pieces[k].on_floor
                     and f.pieces[k].z + f.pieces[k].height > bottom
                     and overlap_matrix(rect[None, :], f.pieces[k].rect[None, :]).any()]
            if under or not can_reach(_reach_corners(rect)):
                continue
            _add(f, space, Placed("curtain", "curtain", variant, x, y, q, model, space.index, 0, rect, None,
                                  z=round(bottom, 4), scale=(1.0, 1.0, round(sz, 4))))
            hung += 1
    return hung


# ---------------------------------------------------------------------------------------
# Cushions


def place_cushions(f: Furnisher, rng: np.random.Generator) -> int:
    """Cushions standing against the back of the seats of :data:`CUSHIONS`; the number placed."""
    placed = 0
    for k in range(len(f.pieces)):
        piece = f.pieces[k]
        rule = CUSHIONS.get(piece.category)
        if rule is None or not piece.on_floor or rng.random() >= rule[0]:
            continue
        seats = [(r, rec) for r, rec in enumerate(piece.model.receptacles) if rec.link == "base"]
        if not seats:
            continue
        r, rec = seats[0]
        n = int(rng.integers(rule[1], rule[2] + 1))
        # A seat's cushions come in one or two designs, taking turns along it.
        variants = [int(v) for v in rng.integers(registry.GENERATED_VARIANTS, size=2)]
        models = [registry.make("cushion", v) for v in variants]
        los = [local_footprint(m) for m in models]
        w = max(float(lo[2] - lo[0]) for lo in los)
        d = max(float(lo[3] - lo[1]) for lo in los)
        (cx, cy), (hx, hy) = rec.center, rec.half_size
        n = min(n, int((2 * hx - 2 * SHELF_MARGIN) // (w + 0.02)))
        if n < 1 or max(float(m.size[2]) for m in models) > rec.clearance or d > 2 * hy:
            continue
        # Spread evenly along the back of the seat.
        xs = np.linspace(cx - hx + SHELF_MARGIN + w / 2, cx + hx - SHELF_MARGIN - w / 2, n) if n > 1 else [cx]
        rot = QUARTER_TURNS[piece.q]
        space = f.spaces[piece.room]
        for j, bx in enumerate(xs):
            variant, model, lo = variants[j % 2], models[j % 2], los[j % 2]
            by = cy - hy + 0.005 - float(lo[1])
            off = rot @ np.array([float(bx), by])
            x, y = piece.x + float(off[0]), piece.y + float(off[1])
            _add(f, space, Placed("cushion", "cushion", variant, x, y, piece.q, model, piece.room, piece.group,
                                  _world_rect(x, y, piece.q, lo), None, z=round(piece.z + rec.height, 4),
                                  support=k, receptacle=r))
            placed += 1
    return placed


# ---------------------------------------------------------------------------------------
# Books


def shelve_books(f: Furnisher, rng: np.random.Generator, can_reach: Callable[[np.ndarray], bool]) -> int:
    """Rows of books on the open, reachable shelves of :data:`BOOK_SHELVES`; the number of books."""
    placed = 0
    for k in range(len(f.pieces)):
        piece = f.pieces[k]
        p = BOOK_SHELVES.get(piece.category)
        if p is None or piece.support is not None:
            continue
        top = float(piece.model.size[2]) - 0.05
        for r, rec in enumerate(piece.model.receptacles):
            if rec.height >= top or not open_receptacle(piece.model, rec) or rng.random() >= p:
                continue
            if not can_reach(receptacle_corners(piece, rec)):
                continue
            placed += _book_row(f, k, r, rec, rng)
    return placed


def _book_row(f: Furnisher, k: int, r: int, rec: Receptacle, rng: np.random.Generator) -> int:
    base = f.pieces[k]
    space = f.spaces[base.room]
    (cx, cy), (hx, hy) = rec.center, rec.half_size
    start, end = cx - hx + SHELF_MARGIN, cx + hx - SHELF_MARGIN
    length = (end - start) * float(rng.uniform(*ROW_FILL))
    from_right = rng.random() < 0.5
    books: list[tuple[int, AssetModel, float]] = []  # variant, model, x of its centre along the row
    cursor, misses = 0.0, 0
    while misses < 3:
        variant = int(rng.integers(BOOK_VARIANTS))
        model = registry.make("shelved_book", variant)
        t, d, h = (float(s) for s in model.size)
        if h > rec.clearance - 0.01 or d > 2 * hy - SHELF_MARGIN:
            misses += 1
            continue
        if cursor + t > length:
            break
        books.append((variant, model, cursor + t / 2))
        cursor += t + BOOK_GAP
    if len(books) < ROW_MIN:
        return 0
    rot = QUARTER_TURNS[base.q]
    for variant, model, along in books:
        lo = local_footprint(model)
        bx = end - along if from_right else start + along
        by = cy - hy + SHELF_MARGIN - float(lo[1])  # its back toward the back of the shelf
        off = rot @ np.array([bx, by])
        x, y = base.x + float(off[0]), base.y + float(off[1])
        _add(f, space, Placed("shelved_book", "shelved_book", variant, x, y, base.q, model, base.room, base.group,
                              _world_rect(x, y, base.q, lo), None, z=round(base.z + rec.height, 4),
                              support=k, receptacle=r))
    return len(books)
