"""Floor plans grown on a grid (after ProcTHOR): rooms, walls, doors and windows.

A house is a set of grid cells (a rectangle, or a rectangle with a corner cut off), each
cell ``cx x cy`` metres, sampled per house. Rooms grow from seed cells: first as
rectangles toward a target size per room type, then cell by cell into L-shapes until every
cell belongs to a room. Of several candidates the one closest to the target sizes and to
a few plausibility rules (bathrooms off a hallway or bedroom, kitchens by the living or
dining room, no corridor-thin bedrooms) is kept.

Geometry: room polygons run counter-clockwise on the wall centre lines, so rooms tile the
house. Each wall segment appears once: a segment lies between one pair of sides (two rooms,
or a room and the exterior) and ``Wall.rooms[0]`` is the room on the *left* of
``start -> end`` (outer walls run so that the room is on their left). Doors form a spanning
tree over adjacent rooms, plus one exterior door; kitchen and living room are sometimes
joined by an open archway (a door without a leaf).
"""

from __future__ import annotations

import bisect
import itertools
from dataclasses import dataclass, field

import numpy as np

from legent_gym.world.generation.roomtypes import ROOM_TYPES
from legent_gym.world.geometry import (
    bounding_box,
    boxes_overlap,
    door_keepout_squares,
    door_leaf_open_segment,
    opening_span,
    polygon_signed_area,
    turn_cross,
)
from legent_gym.world.scene import Door, Wall, Window

OUT, FREE = -1, -2
WALL_THICKNESS = 0.1
#: Least distance from a door or window opening to the end of its wall segment.
OPENING_MARGIN = 0.35
DOOR_WIDTH = 0.9
EXTERIOR_DOOR_WIDTH = 1.0

_DIRS = ((1, 0), (-1, 0), (0, 1), (0, -1))  # (drow, dcol)


class PlanFailed(Exception):
    """No floor plan fits this outline / these targets (the caller retries)."""


def r4(v: float) -> float:
    return round(float(v), 4)


def choice_p(rng: np.random.Generator, p: np.ndarray) -> int:
    """``int(rng.choice(len(p), p=p))`` for valid probabilities: the same draw (one
    ``rng.random()`` against the normalised cumulative sum, as numpy does), without the
    argument checks that cost twice the draw itself."""
    cdf = p.cumsum()
    cdf /= cdf[-1]
    return int(cdf.searchsorted(rng.random(), side="right"))


# ---------------------------------------------------------------------------------------
# The grid: outline, growth, scoring


@dataclass
class GridPlan:
    grid: np.ndarray  #: (rows, cols): room index per cell, or OUT
    cell: tuple[float, float]  #: metres per cell along x and y
    targets: list[int]

    @property
    def area(self) -> float:
        return float((self.grid >= 0).sum() * self.cell[0] * self.cell[1])


def sample_targets(types: list[str], rng: np.random.Generator) -> list[int]:
    """Target size in cells per room, from its type's range."""
    return [int(rng.integers(ROOM_TYPES[t].cells[0], ROOM_TYPES[t].cells[1] + 1)) for t in types]


def outline_options(total: int, single_wide: bool) -> list[tuple[int, int]]:
    """(cols, rows) of rectangles holding ``total`` cells with a little slack, not too
    elongated; a lone room that must be wide gets both sides >= 2."""
    slack = 2 if single_wide else max(1, total // 4)
    opts = []
    for w in range(1, total + slack + 1):
        for h in range(1, total + slack + 1):
            if not (total <= w * h <= total + slack):
                continue
            if max(w, h) > max(2.0, 2.5 * min(w, h)):
                continue
            if single_wide and min(w, h) < 2:
                continue
            opts.append((w, h))
    return opts


def sample_outline(total: int, rng: np.random.Generator, *, single_wide: bool = False) -> np.ndarray:
    """Boolean (rows, cols) mask of the house's cells: a rectangle, maybe minus a corner."""
    opts = outline_options(total, single_wide)
    if not opts:
        raise PlanFailed(f"no outline for {total} cells")
    w, h = opts[int(rng.integers(len(opts)))]
    inside = np.ones((h, w), dtype=bool)
    extra = w * h - total
    if extra >= 1 and w >= 2 and h >= 2 and rng.random() < 0.5:
        cuts = [(cw, ch) for cw in range(1, w) for ch in range(1, h) if cw * ch <= extra]
        cw, ch = cuts[int(rng.integers(len(cuts)))]
        rows = slice(0, ch) if rng.random() < 0.5 else slice(h - ch, h)
        cols = slice(0, cw) if rng.random() < 0.5 else slice(w - cw, w)
        inside[rows, cols] = False
    return inside


def corner_count(mask: np.ndarray) -> int:
    """Vertices of the outline of a cell set (4: rectangle, 6: L); 99 if it pinches at a
    corner (two cells touching only diagonally)."""
    return _corners({(r, c) for r, c in np.argwhere(mask).tolist()})


def _corners(cells: set[tuple[int, int]]) -> int:
    """:func:`corner_count` of the cells ``(row, col)``: each 2x2 window of the padded mask
    with one or three cells set is a vertex; one with a diagonal pair a pinch. Windows away
    from the cells hold none, so only those around their bounding box are looked at."""
    rows = [r for r, _ in cells]
    cols = [c for _, c in cells]
    count = 0
    for y in range(min(rows) - 1, max(rows) + 1):
        for x in range(min(cols) - 1, max(cols) + 1):
            a, b = (y, x) in cells, (y, x + 1) in cells
            c, d = (y + 1, x) in cells, (y + 1, x + 1) in cells
            n = a + b + c + d
            if n == 2 and a == d:
                return 99
            count += n == 1 or n == 3
    return count


def _weighted_choice(rng: np.random.Generator, p: list[float]) -> int:
    """:func:`choice_p` of a list of probabilities, in scalar arithmetic: the same running
    sum, the same division by its last value, the same search, so the same draw."""
    cdf = list(itertools.accumulate(p))
    last = cdf[-1]
    return bisect.bisect_right([c / last for c in cdf], rng.random())


# The growth below works on a list-of-lists grid and per-room cell sets: the grids are a
# few cells across, where numpy's per-call cost outweighs its loops many times over. Every
# random draw is the one the array version makes, in the same order.


def _free_cells(grid: list[list[int]]) -> list[tuple[int, int]]:
    """FREE cells in row-major order (``np.argwhere``'s)."""
    return [(r, c) for r, row in enumerate(grid) for c, v in enumerate(row) if v == FREE]


def _seed_rooms(grid: list[list[int]], targets: list[int], rng: np.random.Generator) -> list[tuple[int, int]]:
    """One seed cell per room, spread apart (largest rooms first); the seeds by room."""
    seeds: dict[int, tuple[int, int]] = {}
    for i in sorted(range(len(targets)), key=lambda k: (-targets[k], k)):
        cells = _free_cells(grid)
        if not cells:
            raise PlanFailed("more rooms than cells")
        if seeds:
            noise = rng.random(len(cells)).tolist()
            placed = list(seeds.values())
            # Manhattan distance to the nearest seed, plus noise: an int plus a float, as
            # numpy adds an int array to a float one.
            spread = [min(abs(r - sr) + abs(c - sc) for sr, sc in placed) + u * 1.5
                      for (r, c), u in zip(cells, noise)]
            pick = spread.index(max(spread))  # the first maximum, as np.argmax
        else:
            pick = int(rng.integers(len(cells)))
        r, c = cells[pick]
        grid[r][c] = i
        seeds[i] = (r, c)
    return [seeds[i] for i in range(len(targets))]


def _grow_rectangles(grid: list[list[int]], targets: list[int], seeds: list[tuple[int, int]],
                     rng: np.random.Generator) -> None:
    """Grow each room's rectangle a row or column at a time toward its target size."""
    h, w = len(grid), len(grid[0])
    rects = {i: [r, c, r + 1, c + 1] for i, (r, c) in enumerate(seeds)}
    area = [1] * len(targets)
    active = [i for i in range(len(targets)) if area[i] < targets[i]]
    while active:
        deficit = [float(targets[i] - area[i]) for i in active]
        total = sum(deficit)  # whole numbers: exact in any order, as numpy's sum
        i = active[_weighted_choice(rng, [d / total for d in deficit])]
        r0, c0, r1, c1 = rects[i]
        grown = False
        for d in rng.permutation(4).tolist():
            dr, dc = _DIRS[d]
            if dr:
                row = r1 if dr > 0 else r0 - 1
                if not 0 <= row < h:
                    continue
                line = [(row, c) for c in range(c0, c1)]
            else:
                col = c1 if dc > 0 else c0 - 1
                if not 0 <= col < w:
                    continue
                line = [(r, col) for r in range(r0, r1)]
            if any(grid[r][c] != FREE for r, c in line) or area[i] + len(line) > targets[i] + 1:
                continue
            for r, c in line:
                grid[r][c] = i
            area[i] += len(line)
            rects[i] = [r0 - (dr < 0), c0 - (dc < 0), r1 + (dr > 0), c1 + (dc > 0)]
            grown = True
            break
        if not grown or area[i] >= targets[i]:
            active.remove(i)


def _fill_free(grid: list[list[int]], targets: list[int], rng: np.random.Generator) -> None:
    """Give every remaining free cell to a neighbouring room, keeping rooms rectangles or
    L-shapes; rooms short of their target are preferred."""
    h, w = len(grid), len(grid[0])
    members: dict[int, set[tuple[int, int]]] = {}
    for r, row in enumerate(grid):
        for c, v in enumerate(row):
            if v >= 0:
                members.setdefault(v, set()).add((r, c))
    while True:
        free = _free_cells(grid)
        if not free:
            return
        options, weights = [], []
        for r, c in free:
            rooms = sorted({grid[r + dr][c + dc] for dr, dc in _DIRS
                            if 0 <= r + dr < h and 0 <= c + dc < w and grid[r + dr][c + dc] >= 0})
            for i in rooms:
                cells = members[i] | {(r, c)}
                corners = _corners(cells)
                if corners > 6:
                    continue
                short = max(0, targets[i] - len(cells) + 1)
                options.append((r, c, i))
                weights.append(1.0 + 3.0 * short + (2.0 if corners == 4 else 0.0))
        if not options:
            raise PlanFailed("a free cell cannot join any room as a rectangle or L")
        total = sum(weights)
        r, c, i = options[_weighted_choice(rng, [x / total for x in weights])]
        grid[r][c] = i
        members[i].add((r, c))


def grow_rooms(inside: np.ndarray, targets: list[int], rng: np.random.Generator) -> np.ndarray:
    """One candidate: room index per cell (OUT outside the house)."""
    grid = [[FREE if v else OUT for v in row] for row in inside.tolist()]
    seeds = _seed_rooms(grid, targets, rng)
    _grow_rectangles(grid, targets, seeds, rng)
    _fill_free(grid, targets, rng)
    return np.array(grid, dtype=np.int64)


def score_plan(grid: np.ndarray, targets: list[int], types: list[str]) -> float:
    """Lower is better: size error per room, plus penalties for implausible layouts."""
    cells = grid.tolist()
    h, w = len(cells), len(cells[0])
    by_room: dict[int, list[tuple[int, int]]] = {}
    for r, row in enumerate(cells):
        for c, v in enumerate(row):
            by_room.setdefault(v, []).append((r, c))
    score = 0.0
    for i, (t, rtype) in enumerate(zip(targets, types)):
        mine = by_room[i]
        a = len(mine)
        rr = [r for r, _ in mine]
        cc = [c for _, c in mine]
        bh, bw = max(rr) - min(rr) + 1, max(cc) - min(cc) + 1
        if a < ROOM_TYPES[rtype].cells[0]:
            return np.inf  # smaller than any room of its type
        score += abs(a - t) / t
        if a != bh * bw:
            score += 0.4  # an L-shape
        if ROOM_TYPES[rtype].wide and min(bh, bw) == 1:
            score += 3.0  # a corridor-thin bedroom or living room rarely holds its furniture
        if rtype == "hallway" and min(bh, bw) == 1:
            score -= 0.3
        if max(bh, bw) > 3 * min(bh, bw):
            score += 0.5
    pairs = {(min(x, y), max(x, y)) for r, row in enumerate(cells) for c, x in enumerate(row)
             for y in (cells[r + 1][c] if r + 1 < h else OUT, row[c + 1] if c + 1 < w else OUT)
             if x != y and x >= 0 and y >= 0}

    def neighbours(i: int) -> set[str]:
        return {types[b if a == i else a] for a, b in pairs if i in (a, b)}

    present = set(types)
    for i, rtype in enumerate(types):
        near = neighbours(i)
        if rtype == "bathroom" and len(types) > 2 and not near & {"hallway", "bedroom", "living_room"}:
            score += 0.5
        if rtype == "kitchen" and present & {"living_room", "dining_room"} and not near & {"living_room", "dining_room"}:
            score += 0.5
        if rtype == "hallway":
            score -= 0.25 * len(near)

    def outdoors(r: int, c: int) -> bool:
        return not (0 <= r < h and 0 <= c < w) or cells[r][c] == OUT

    def touches_outside(i: int) -> bool:
        return any(outdoors(r + dr, c + dc) for r, c in by_room[i] for dr, dc in _DIRS)

    if len(types) > 1 and not any(ROOM_TYPES[t].public and touches_outside(i) for i, t in enumerate(types)):
        score += 2.0
    return score


def plan_grid(types: list[str], rng: np.random.Generator, *, cell_range: tuple[float, float],
              area: tuple[float, float] | None = None, candidates: int = 16,
              targets: list[int] | None = None) -> GridPlan:
    """The best of several grown candidates for these room types (``targets``: size in
    cells per room; drawn from the room types' ranges when None).

    Raises :class:`PlanFailed` when no candidate is valid (the caller retries)."""
    targets = sample_targets(types, rng) if targets is None else list(targets)
    cell = (r4(rng.uniform(*cell_range)), r4(rng.uniform(*cell_range)))
    single_wide = len(types) == 1 and ROOM_TYPES[types[0]].wide
    inside = sample_outline(sum(targets), rng, single_wide=single_wide)
    if area is not None:
        house_area = inside.sum() * cell[0] * cell[1]
        if not area[0] <= house_area <= area[1]:
            raise PlanFailed(f"house area {house_area:.1f} m^2 outside {area}")
    if len(types) > int(inside.sum()):
        raise PlanFailed("more rooms than cells")
    best, best_score = None, np.inf
    for _ in range(1 if len(types) == 1 else candidates):
        try:
            grid = grow_rooms(inside, targets, rng)
        except PlanFailed:
            continue
        s = score_plan(grid, targets, types)
        if np.isfinite(s) and s < best_score:
            best, best_score = grid, s
    if best is None:
        raise PlanFailed("no valid room layout")
    return GridPlan(best, cell, targets)


# ---------------------------------------------------------------------------------------
# Geometry: polygons and walls


def room_polygon(grid: np.ndarray, i: int, cell: tuple[float, float]) -> list[tuple[float, float]]:
    """Counter-clockwise outline of room ``i`` (metres), without collinear vertices."""
    h, w = grid.shape
    nxt: dict[tuple[int, int], tuple[int, int]] = {}
    for r, c in np.argwhere(grid == i).tolist():
        def other(rr: int, cc: int) -> bool:
            return not (0 <= rr < h and 0 <= cc < w and grid[rr, cc] == i)
        # Cell edges walked counter-clockwise (x = col, y = row); keep the outline ones.
        if other(r - 1, c):
            nxt[(c, r)] = (c + 1, r)
        if other(r, c + 1):
            nxt[(c + 1, r)] = (c + 1, r + 1)
        if other(r + 1, c):
            nxt[(c + 1, r + 1)] = (c, r + 1)
        if other(r, c - 1):
            nxt[(c, r + 1)] = (c, r)
    start = min(nxt, key=lambda p: (p[1], p[0]))
    loop, p = [start], nxt[start]
    while p != start:
        loop.append(p)
        p = nxt[p]
    pts = [q for k, q in enumerate(loop) if turn_cross(loop[k - 1], q, loop[(k + 1) % len(loop)]) != 0]
    # Start at the lowest-left corner for a stable order.
    k0 = min(range(len(pts)), key=lambda k: (pts[k][1], pts[k][0]))
    pts = pts[k0:] + pts[:k0]
    return [(r4(x * cell[0]), r4(y * cell[1])) for x, y in pts]


@dataclass
class WallRun:
    """A wall on the grid, before it gets an id: rooms[0] is on the left of start -> end."""

    start: tuple[int, int]  # grid point (col, row)
    end: tuple[int, int]
    left: int
    right: int  # OUT for the exterior


def wall_runs(grid: np.ndarray) -> list[WallRun]:
    """Maximal straight runs of cell edges with the same room on each side."""
    h, w = grid.shape
    p = np.pad(grid, 1, constant_values=OUT)
    runs: list[WallRun] = []
    # Horizontal grid lines y = j: above is the left side of a +x wall.
    for j in range(h + 1):
        below, above = p[j, 1:-1], p[j + 1, 1:-1]
        runs += _runs_on_line(above.tolist(), below.tolist(), lambda k, j=j: (k, j))
    # Vertical grid lines x = i: the cell to the left is the left side of a +y wall.
    for i in range(w + 1):
        left, right = p[1:-1, i], p[1:-1, i + 1]
        runs += _runs_on_line(left.tolist(), right.tolist(), lambda k, i=i: (i, k))
    return runs


def _runs_on_line(lefts: list[int], rights: list[int], point) -> list[WallRun]:
    out: list[WallRun] = []
    k = 0
    n = len(lefts)
    while k < n:
        a, b = lefts[k], rights[k]
        if a == b:
            k += 1
            continue
        m = k
        while m + 1 < n and lefts[m + 1] == a and rights[m + 1] == b:
            m += 1
        start, end = point(k), point(m + 1)
        if a == OUT:  # run it the other way so the room is on its left
            out.append(WallRun(end, start, b, OUT))
        else:
            out.append(WallRun(start, end, a, b))
        k = m + 1
    return out


# ---------------------------------------------------------------------------------------
# The floor plan with walls, doors and windows


@dataclass
class FloorPlan:
    types: list[str]
    room_ids: list[str]
    polygons: list[list[tuple[float, float]]]
    walls: list[Wall]
    wall_sides: list[tuple[int, int]]  #: (left room, right room or OUT) per wall
    grid: GridPlan
    doors: list[Door] = field(default_factory=list)
    windows: list[Window] = field(default_factory=list)

    def walls_between(self, a: int, b: int) -> list[int]:
        return [k for k, (x, y) in enumerate(self.wall_sides) if {x, y} == {a, b}]

    def exterior_walls(self, a: int) -> list[int]:
        return [k for k, (x, y) in enumerate(self.wall_sides) if x == a and y == OUT]

    def adjacency(self) -> list[tuple[int, int]]:
        return sorted({(min(x, y), max(x, y)) for x, y in self.wall_sides if y != OUT})


def room_ids_for(types: list[str]) -> list[str]:
    """"bedroom", "bedroom_2", "living_room", ... (stable, readable)."""
    seen: dict[str, int] = {}
    ids = []
    for t in types:
        seen[t] = seen.get(t, 0) + 1
        ids.append(t if seen[t] == 1 else f"{t}_{seen[t]}")
    return ids


def build_floorplan(plan: GridPlan, types: list[str], *, wall_height: float) -> FloorPlan:
    ids = room_ids_for(types)
    polys = [room_polygon(plan.grid, i, plan.cell) for i in range(len(types))]
    walls, sides = [], []
    cx, cy = plan.cell
    for k, run in enumerate(wall_runs(plan.grid)):
        rooms = [ids[run.left], "exterior" if run.right == OUT else ids[run.right]]
        walls.append(Wall(id=f"wall_{k}", start=(r4(run.start[0] * cx), r4(run.start[1] * cy)),
                          end=(r4(run.end[0] * cx), r4(run.end[1] * cy)), height=wall_height,
                          thickness=WALL_THICKNESS, rooms=rooms))
        sides.append((run.left, run.right))
    return FloorPlan(types, ids, polys, walls, sides, plan)


def _link_cost(ta: str, tb: str) -> float:
    """How much we dislike a door between two room types (a hallway links anything)."""
    pair = {ta, tb}
    if "hallway" in pair:
        return 0.0
    if "living_room" in pair:
        return 0.8 if "bathroom" in pair else 0.3
    if pair in ({"kitchen", "dining_room"}, {"dining_room"}):
        return 0.2
    if "bathroom" in pair:
        return 1.5 if "bedroom" in pair else 2.5
    if pair == {"bedroom"}:
        return 2.0
    return 1.0


def _door_offset(length: float, width: float, rng: np.random.Generator) -> float | None:
    lo, hi = OPENING_MARGIN + width / 2, length - OPENING_MARGIN - width / 2
    if hi < lo:
        return None
    return round(float(rng.uniform(lo, hi)), 3)


def place_doors(fp: FloorPlan, rng: np.random.Generator, *, openness: float = 1.0) -> None:
    """Doors over a spanning tree of adjacent rooms (cheap links first), an archway between
    kitchen and living room half the time, and one exterior door."""
    types = fp.types
    pairs = fp.adjacency()
    costs = {p: _link_cost(types[p[0]], types[p[1]]) + float(rng.random()) * 0.6 for p in pairs}
    arch = None
    kl = [p for p in pairs if {types[p[0]], types[p[1]]} == {"kitchen", "living_room"}]
    if kl and rng.random() < 0.5:
        arch = kl[0]
        costs[arch] = -1.0
    parent = list(range(len(types)))

    def find(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for p in sorted(pairs, key=lambda q: (costs[q], q)):
        ra, rb = find(p[0]), find(p[1])
        if ra == rb:
            continue
        door = _fitting_door(fp, lambda p=p: _door_between(fp, p, rng, archway=p == arch, openness=openness), rng)
        if door is None:
            continue
        parent[ra] = rb
        fp.doors.append(door)
    if len({find(i) for i in range(len(types))}) > 1:
        raise PlanFailed("rooms cannot all be linked by doors")
    front = _fitting_door(fp, lambda: _exterior_door(fp, rng, openness), rng, exterior=True)
    if front is None:
        raise PlanFailed("no room for the front door")
    fp.doors.append(front)
    for k, d in enumerate(fp.doors):
        d.id = f"door_{k}"


def add_door(fp: FloorPlan, pair: tuple[int, int], rng: np.random.Generator, *, openness: float = 1.0) -> bool:
    """A door between two adjacent rooms where one fits; False where none does. Doors are
    renumbered ``door_0``, ``door_1``, ... in order."""
    door = _fitting_door(fp, lambda: _door_between(fp, pair, rng, archway=False, openness=openness), rng)
    if door is None:
        return False
    fp.doors.append(door)
    for k, d in enumerate(fp.doors):
        d.id = f"door_{k}"
    return True


def _door_zones(fp: FloorPlan, door: Door) -> tuple[list[np.ndarray], np.ndarray | None]:
    """(free squares in front of the door, open-leaf slab) as boxes."""
    wall = next(w for w in fp.walls if w.id == door.wall)
    squares = [bounding_box(q) for q in door_keepout_squares(wall, door)]
    leaf = None
    if door.leaf:
        a, b = door_leaf_open_segment(wall, door)
        leaf = np.concatenate([np.minimum(a, b) - 0.03, np.maximum(a, b) + 0.03])
    return squares, leaf


def _door_conflicts(fp: FloorPlan, door: Door) -> bool:
    """Whether a door's squares or leaf run into another door's squares or leaf (a leaf
    swinging across another doorway, two doors sharing a corner)."""
    sq, leaf = _door_zones(fp, door)
    mine = sq + ([leaf] if leaf is not None else [])
    for other in fp.doors:
        osq, oleaf = _door_zones(fp, other)
        theirs = osq + ([oleaf] if oleaf is not None else [])
        if any(boxes_overlap(a, b) for a in mine for b in theirs):
            return True
    return False


def _fitting_door(fp: FloorPlan, make, rng: np.random.Generator, *, exterior: bool = False, tries: int = 6):
    """A door from ``make`` (offsets are random) whose hinge and swing keep it clear of the
    doors already placed; None if none of a few tries fits."""
    for _ in range(tries):
        door = make()
        if door is None:
            return None
        sides = ("left",) if exterior else ("left", "right")
        combos = [(h, s) for h in ("start", "end") for s in sides]
        for k in rng.permutation(len(combos)).tolist():
            door.hinge, door.swing = combos[k]
            if not _door_conflicts(fp, door):
                return door
    return None


def _door_between(fp: FloorPlan, pair: tuple[int, int], rng: np.random.Generator, *, archway: bool,
                  openness: float) -> Door | None:
    walls = [k for k in fp.walls_between(*pair) if fp.walls[k].length >= DOOR_WIDTH + 2 * OPENING_MARGIN]
    if not walls:
        return None
    k = max(walls, key=lambda j: (round(fp.walls[j].length, 3), -j))
    wall = fp.walls[k]
    width = DOOR_WIDTH
    if archway:
        width = round(float(rng.uniform(1.2, max(1.2, min(2.0, wall.length - 2 * OPENING_MARGIN)))), 3)
    offset = _door_offset(wall.length, width, rng)
    if offset is None:
        return None
    return Door(id="door", wall=wall.id, offset=offset, width=width, leaf=not archway,
                hinge="start" if rng.random() < 0.5 else "end",
                swing="left" if rng.random() < 0.5 else "right",
                openness=openness, connects=list(wall.rooms))


_FRONT_DOOR_ORDER = ("living_room", "hallway", "kitchen", "dining_room", "office", "bedroom", "bathroom")


def _exterior_door(fp: FloorPlan, rng: np.random.Generator, openness: float) -> Door:
    for rtype in _FRONT_DOOR_ORDER:
        rooms = [i for i, t in enumerate(fp.types) if t == rtype]
        for i in rng.permutation(len(rooms)).tolist() if rooms else []:
            walls = [k for k in fp.exterior_walls(rooms[i])
                     if fp.walls[k].length >= EXTERIOR_DOOR_WIDTH + 2 * OPENING_MARGIN]
            if not walls:
                continue
            wall = fp.walls[walls[int(rng.integers(len(walls)))]]
            offset = _door_offset(wall.length, EXTERIOR_DOOR_WIDTH, rng)
            if offset is None:  # never: the walls kept are long enough
                raise PlanFailed(f"wall {wall.id} is too short for the front door")
            # Outer walls have their room on the left: the leaf swings inward.
            return Door(id="door", wall=wall.id, offset=offset, width=EXTERIOR_DOOR_WIDTH, leaf=True,
                        hinge="start" if rng.random() < 0.5 else "end", swing="left",
                        openness=openness, connects=[wall.rooms[0], "exterior"])
    raise PlanFailed("no outer wall can hold the front door")


def place_windows(fp: FloorPlan, rng: np.random.Generator) -> None:
    """Windows in outer walls, clear of doors: usually one per room, two in big rooms."""
    sill = 0.9
    height = round(min(1.2, fp.walls[0].height - sill - 0.5), 3) if fp.walls else 1.2
    if height < 0.5:
        return
    door_spans: dict[str, list[tuple[float, float]]] = {}
    for d in fp.doors:
        lo, hi = opening_span(d)
        door_spans.setdefault(d.wall, []).append((lo - 0.3, hi + 0.3))
    for i in range(len(fp.types)):
        walls = [k for k in fp.exterior_walls(i) if fp.walls[k].length >= 2.0]
        if not walls:
            continue
        area = abs(polygon_signed_area(fp.polygons[i]))
        count = (2 if area > 15 and rng.random() < 0.4 else 1) if rng.random() < 0.85 else 0
        for k in rng.permutation(len(walls))[:count].tolist():
            wall = fp.walls[walls[k]]
            width = round(float(rng.uniform(0.8, min(1.6, wall.length - 1.2))), 3)
            offset = _door_offset(wall.length, width, rng)
            if offset is None:
                continue
            lo, hi = offset - width / 2, offset + width / 2
            if any(lo < b and a < hi for a, b in door_spans.get(wall.id, [])):
                continue
            fp.windows.append(Window(id=f"window_{len(fp.windows)}", wall=wall.id, offset=offset,
                                     width=width, height=height, sill=sill))

