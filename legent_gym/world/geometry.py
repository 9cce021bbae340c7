"""Floor-plane geometry of a scene: walls, door and window openings, door leaves, footprints,
rectangles and polygons.

The scene format (:mod:`legent_gym.world.scene`) says where walls, doors and objects are;
this module says what floor they take. The builder, the navigation grid, the top-down map
and the house generator all ask it, so they agree to the last bit on where a door's hinge
is or which floor a footprint covers.

Conventions: metres on the floor plane ``(x, y)``; angles in degrees, counter-clockwise
from +x. A *box* is an axis-aligned rectangle ``(x0, y0, x1, y1)``; *corners* are a (4, 2)
array of a rectangle in any orientation, counter-clockwise. Positions along a wall are
metres from its start. Several helpers come in a scalar and a vectorised form; each keeps
its callers' exact arithmetic, since generated houses must not change by a bit.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, cast

import numpy as np

from legent_gym.world.assets import registry

if TYPE_CHECKING:  # the scene format imports this module: no import of it at run time
    from legent_gym.world.assets.model import AssetModel
    from legent_gym.world.scene import Door, ObjectInstance, Scene, Wall, Window

#: Overlap (metres) that two boxes may share and still count as apart in :func:`overlap_matrix`.
OVERLAP_SLACK = 1e-6
#: The deepest free square kept in front of an archway (a door without a leaf), metres.
ARCHWAY_KEEPOUT_DEPTH = 0.9


# ---------------------------------------------------------------------------------------
# Walls and their openings


def wall_frame(wall: Wall) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(start, unit direction, left unit normal, length in metres) of a wall."""
    start = np.asarray(wall.start, dtype=np.float64)
    d = np.asarray(wall.end, dtype=np.float64) - start
    length = wall.length  # the scene's own length, the one openings are checked against
    u = d / length if length > 0 else np.array([1.0, 0.0])
    return start, u, np.array([-u[1], u[0]]), length


def heading_deg(direction: Sequence[float] | np.ndarray) -> float:
    """Heading of a direction vector in degrees (0 along +x, counter-clockwise)."""
    return math.degrees(math.atan2(direction[1], direction[0]))


def opening_span(item: Door | Window) -> tuple[float, float]:
    """(start, end) of a door's or window's opening, metres along its wall."""
    return item.offset - item.width / 2, item.offset + item.width / 2


def door_passable(door: Door) -> bool:
    """An archway, or a door more than half open."""
    return (not door.leaf) or door.openness > 0.5


def door_leads_outside(wall: Wall, door: Door) -> bool:
    """Whether the door opens onto the outside (its wall, or the door, names "exterior")."""
    return "exterior" in wall.rooms or "exterior" in door.connects


def wall_solid_spans(wall: Wall, doors: Iterable[Door], *, cut_closed: bool = False) -> list[tuple[float, float]]:
    """Intervals ``(a, b)`` (metres along the wall) where it is solid at floor level.

    The openings of passable doors are cut out (of every door with ``cut_closed``);
    windows count as solid (they are above the floor).
    """
    length = wall.length
    cuts = sorted(opening_span(d) for d in doors if d.wall == wall.id and (cut_closed or door_passable(d)))
    spans, cursor = [], 0.0
    for a, b in cuts:
        if a > cursor + 1e-9:
            spans.append((cursor, min(a, length)))
        cursor = max(cursor, b)
    if cursor < length - 1e-9:
        spans.append((cursor, length))
    return spans


def wall_boxes(scene: Scene) -> list[tuple[str, np.ndarray]]:
    """(wall id, corners) of each solid wall piece at floor level, the full thickness wide.

    Every door's opening is cut out, open or closed: furniture in a doorway is a door
    clearance problem, not a wall one.
    """
    out = []
    for wall in scene.walls:
        start, u, n, _ = wall_frame(wall)
        t = wall.thickness / 2
        doors = [d for d in scene.doors if d.wall == wall.id]
        for a, b in wall_solid_spans(wall, doors, cut_closed=True):
            p0, p1 = start + u * a, start + u * b
            out.append((wall.id, np.array([p0 - n * t, p1 - n * t, p1 + n * t, p0 + n * t])))
    return out


# ---------------------------------------------------------------------------------------
# Doors


def door_hinge_offset(door: Door) -> float:
    """Where the hinge is, metres along the wall: the end of the opening named by ``door.hinge``."""
    a, b = opening_span(door)
    return a if door.hinge == "start" else b


def door_hinge_point(wall: Wall, door: Door) -> np.ndarray:
    """World (x, y) of the door's hinge axis, on the wall's centre line."""
    start, u, _, _ = wall_frame(wall)
    return start + u * door_hinge_offset(door)


def door_swing_normal(wall: Wall, door: Door) -> np.ndarray:
    """Unit vector across the wall toward the side the leaf swings to."""
    _, _, left, _ = wall_frame(wall)
    return left if door.swing == "left" else -left


def door_leaf_open_segment(wall: Wall, door: Door) -> tuple[np.ndarray, np.ndarray]:
    """(hinge, tip) of a fully open leaf: perpendicular to the wall, the door's width long."""
    hinge = door_hinge_point(wall, door)
    return hinge, hinge + door_swing_normal(wall, door) * door.width


def door_keepout_depth(door: Door) -> float:
    """How deep (metres) the free square in front of a door reaches: a leaf's swing (its
    width), or at most :data:`ARCHWAY_KEEPOUT_DEPTH` for an archway."""
    return door.width if door.leaf else min(door.width, ARCHWAY_KEEPOUT_DEPTH)


def door_keepout_squares(wall: Wall, door: Door, depth: float | None = None) -> list[np.ndarray]:
    """Corners of the free squares in front of a door on both sides of its wall (left side
    first), from the wall faces: the opening wide and ``depth`` metres deep (default
    :func:`door_keepout_depth`)."""
    start, u, left, _ = wall_frame(wall)
    depth = door_keepout_depth(door) if depth is None else depth
    half_t = wall.thickness / 2
    centre = start + u * door.offset
    squares = []
    for side in (left, -left):
        base = centre + side * half_t
        a = base - u * door.width / 2
        b = base + u * door.width / 2
        squares.append(np.array([a, b, b + side * depth, a + side * depth]))
    return squares


# ---------------------------------------------------------------------------------------
# Turns and rectangles


def rotation_matrix(yaw_deg: float) -> np.ndarray:
    """2x2 matrix turning a vector ``yaw_deg`` degrees counter-clockwise (quarter turns exact)."""
    a = math.radians(yaw_deg)
    c, s = math.cos(a), math.sin(a)
    # Snap exact quarter turns so axis-aligned pieces stay exactly axis-aligned.
    c, s = (round(c) if abs(c - round(c)) < 1e-12 else c), (round(s) if abs(s - round(s)) < 1e-12 else s)
    return np.array([[c, -s], [s, c]])


#: ``QUARTER_TURNS[q]`` turns a vector by ``q`` quarter turns counter-clockwise (exact).
QUARTER_TURNS = np.array([[[1, 0], [0, 1]], [[0, -1], [1, 0]], [[-1, 0], [0, -1]], [[0, 1], [-1, 0]]],
                         dtype=np.float64)


def quarter_turns_facing(normal: Sequence[float]) -> int:
    """Quarter turns (0..3) that point a model's front (+y) along an axis-aligned unit ``normal``."""
    return {(0, 1): 0, (-1, 0): 1, (0, -1): 2, (1, 0): 3}[(int(round(normal[0])), int(round(normal[1])))]


def turned_rect(local: np.ndarray, q: int) -> np.ndarray:
    """Box offsets ``(x0, y0, x1, y1)`` of the local box ``local`` turned by ``q`` quarter turns."""
    x0, y0, x1, y1 = local
    return np.array([(x0, y0, x1, y1), (-y1, x0, -y0, x1), (-x1, -y1, -x0, -y0), (y0, -x1, y1, -x0)][q % 4])


def rect_corners(center: Sequence[float], local: Sequence[float], yaw_deg: float) -> np.ndarray:
    """Corners of the local box ``(xmin, ymin, xmax, ymax)`` turned by ``yaw_deg`` and moved to ``center``."""
    x0, y0, x1, y1 = local
    pts = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=np.float64)
    return pts @ rotation_matrix(yaw_deg).T + np.asarray(center[:2], dtype=np.float64)


def bounding_box(points: np.ndarray) -> np.ndarray:
    """Box ``(x0, y0, x1, y1)`` around (N, 2) points."""
    return np.concatenate([points.min(axis=0), points.max(axis=0)])


def expand(boxes: np.ndarray, margin: float) -> np.ndarray:
    """Boxes (N, 4) grown by ``margin`` metres on every side (shrunk when negative)."""
    return boxes + np.array([-margin, -margin, margin, margin])


def boxes_overlap(a: Sequence[float] | np.ndarray, b: Sequence[float] | np.ndarray) -> bool:
    """Whether two boxes overlap with positive area (boxes that only touch do not)."""
    return bool(a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3])


def overlap_matrix(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(A, B) booleans: boxes ``a[i]`` and ``b[j]`` overlap by more than :data:`OVERLAP_SLACK`."""
    if len(a) == 0 or len(b) == 0:
        return np.zeros((len(a), len(b)), dtype=bool)
    a, b = a[:, None, :], b[None, :, :]
    eps = OVERLAP_SLACK
    return ((a[..., 0] < b[..., 2] - eps) & (b[..., 0] < a[..., 2] - eps)
            & (a[..., 1] < b[..., 3] - eps) & (b[..., 1] < a[..., 3] - eps))


def points_in_rect(pts: np.ndarray, corners: np.ndarray, tol: float) -> np.ndarray:
    """(N,) booleans: points (N, 2) within the rectangle ``corners``, ``tol`` metres of slack."""
    o = corners[0]
    e0, e1 = corners[1] - o, corners[3] - o
    l0, l1 = float(np.hypot(*e0)), float(np.hypot(*e1))
    rel = pts - o
    s, t = rel @ e0 / l0, rel @ e1 / l1
    return (s >= -tol) & (s <= l0 + tol) & (t >= -tol) & (t <= l1 + tol)


def closest_points_on_rect(corners: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """(N, 2) points of the filled rectangle ``corners`` closest to each of ``pts`` (N, 2)."""
    o = corners[0]
    e0, e1 = corners[1] - o, corners[3] - o
    l0, l1 = float(e0 @ e0), float(e1 @ e1)
    rel = pts - o
    s = np.clip(rel @ e0 / max(l0, 1e-12), 0.0, 1.0)
    t = np.clip(rel @ e1 / max(l1, 1e-12), 0.0, 1.0)
    return o + s[:, None] * e0 + t[:, None] * e1


def axis_aligned_closest(corners: np.ndarray, xs: np.ndarray, ys: np.ndarray
                         ) -> tuple[np.ndarray, np.ndarray] | None:
    """:func:`closest_points_on_rect` for a grid, split by axis: the nearest x per ``xs`` and
    nearest y per ``ys``, bit for bit; ``None`` unless the rectangle's edges lie along the axes.

    It takes edges with exact zeros only: a dot product with an exact zero term is the
    other product, rounded once, so the split arithmetic is the same.
    """
    o = corners[0]
    e0, e1 = corners[1] - o, corners[3] - o
    if e0[1] == 0.0 and e1[0] == 0.0:
        ex, ey, lx, ly = e0[0], e1[1], float(e0 @ e0), float(e1 @ e1)
    elif e0[0] == 0.0 and e1[1] == 0.0:
        ex, ey, lx, ly = e1[0], e0[1], float(e1 @ e1), float(e0 @ e0)
    else:
        return None
    sx = np.clip((xs - o[0]) * ex / max(lx, 1e-12), 0.0, 1.0)
    sy = np.clip((ys - o[1]) * ey / max(ly, 1e-12), 0.0, 1.0)
    return o[0] + sx * ex + 0.0, o[1] + sy * ey + 0.0


def penetration(a: np.ndarray, b: np.ndarray) -> float:
    """How deep (metres) two convex quadrilaterals (corners) overlap; <= 0 when apart or touching."""
    depth = np.inf
    for poly in (a, b):
        for e in poly[1:3] - poly[:2]:  # a rectangle's other two edges are parallel to these
            n = np.array([-e[1], e[0]])
            norm = float(np.hypot(*n))
            if norm < 1e-12:
                continue
            n /= norm
            pa, pb = a @ n, b @ n
            depth = min(depth, min(pa.max() - pb.min(), pb.max() - pa.min()))
            if depth <= 0:
                return float(depth)
    return float(depth)


# ---------------------------------------------------------------------------------------
# Polygons


def turn_cross(a: Sequence[float], b: Sequence[float], c: Sequence[float]) -> float:
    """z of ``(b - a) x (c - b)``: > 0 where a -> b -> c turns left, 0 where collinear."""
    return (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])


def polygon_signed_area(polygon: Iterable[tuple[float, float]]) -> float:
    """Area in square metres, positive for a counter-clockwise polygon (shoelace formula)."""
    pts = list(polygon)
    return 0.5 * sum(
        x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1], strict=True)
    )


def polygon_centroid(polygon: Sequence[Sequence[float]] | np.ndarray) -> np.ndarray:
    """Centroid (x, y) of the area of a simple polygon."""
    p = np.asarray(polygon, dtype=np.float64)
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * area)


def inside_polygon(x: np.ndarray, y: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Booleans, of ``x`` and ``y`` broadcast together: points inside the polygon (M, 2), by
    the even-odd rule."""
    pts = np.asarray(poly, dtype=np.float64).tolist()  # edges by plain floats: the same arithmetic
    inside = np.zeros(np.broadcast_shapes(np.shape(x), np.shape(y)), dtype=bool)
    for (xa, ya), (xb, yb) in zip(pts, pts[1:] + pts[:1]):
        if ya == yb:
            continue
        crosses = (ya > y) != (yb > y)
        if xa == xb:  # a vertical edge: x_at below is xa plus a zero, which compares as xa
            inside ^= crosses & (x < xa)
            continue
        x_at = xa + (y - ya) * (xb - xa) / (yb - ya)
        inside ^= crosses & (x < x_at)
    return inside


def points_in_polygon(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """(N,) booleans: points (N, 2) inside the polygon (M, 2), by the even-odd rule."""
    pts = np.asarray(pts, dtype=np.float64)
    return inside_polygon(pts[:, 0], pts[:, 1], poly)


def inset_polygon(poly: np.ndarray, d: float) -> np.ndarray:
    """A counter-clockwise rectilinear polygon moved ``d`` metres inward (each vertex by the
    inward normals of its two edges)."""
    prev_e = poly - np.roll(poly, 1, axis=0)
    next_e = np.roll(poly, -1, axis=0) - poly
    n_prev = np.column_stack([-prev_e[:, 1], prev_e[:, 0]]) / np.linalg.norm(prev_e, axis=1)[:, None]
    n_next = np.column_stack([-next_e[:, 1], next_e[:, 0]]) / np.linalg.norm(next_e, axis=1)[:, None]
    return poly + d * (n_prev + n_next)


def rects_in_polygon(boxes: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """(N,) booleans: boxes (N, 4) inside a rectilinear polygon (touching its edges allowed)."""
    if len(boxes) == 0:
        return np.zeros(0, dtype=bool)
    r = expand(boxes, -1e-5)
    corners = np.stack([r[:, [0, 1]], r[:, [2, 1]], r[:, [2, 3]], r[:, [0, 3]]], axis=1).reshape(-1, 2)
    ok = points_in_polygon(corners, poly).reshape(-1, 4).all(axis=1)
    vx, vy = poly[:, 0][None, :], poly[:, 1][None, :]
    vertex_inside = ((vx > r[:, 0:1]) & (vx < r[:, 2:3]) & (vy > r[:, 1:2]) & (vy < r[:, 3:4])).any(axis=1)
    # .all/.any along an axis of a 2-D array give arrays (numpy's types allow a scalar)
    return cast(np.ndarray, ok & ~vertex_inside)


# ---------------------------------------------------------------------------------------
# Footprints of objects


def yaw_of(obj: ObjectInstance) -> float:
    """The object's heading in degrees (its rotation about z)."""
    return float(obj.rotation[2])


#: Static objects resting on nothing whose base is this high (metres) or higher hang on a
#: wall (a picture): they block no floor.
HANGING_HEIGHT = 0.5


def is_floor_furniture(obj: ObjectInstance) -> bool:
    """Furniture standing on the floor (static, resting on nothing, its base on the floor
    rather than hung on a wall): what blocks the floor."""
    return obj.kind == "static" and obj.on is None and obj.position[2] < HANGING_HEIGHT


def local_footprint(model: AssetModel) -> np.ndarray:
    """Box ``(x0, y0, x1, y1)`` of an asset model's footprint in its own frame."""
    return model.footprint()


def asset_local_bounds(scene: Scene | None, obj: ObjectInstance) -> np.ndarray | None:
    """The object's scaled bounds ``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` in its own
    frame; ``None`` when the asset is unknown (an import without a size)."""
    scale = np.asarray(obj.scale, dtype=np.float64)
    if scene is not None:
        for imported in scene.assets:
            if imported.id == obj.asset:
                if imported.size is None:
                    return None
                size = np.asarray(imported.size, dtype=np.float64)
                if getattr(imported, "yaw", 0) % 180 == 90:  # the size is the file's, before the turn
                    size = size[[1, 0, 2]]
                size = size * scale
                return np.array([[-size[0] / 2, -size[1] / 2, 0.0], [size[0] / 2, size[1] / 2, size[2]]])
    if not registry.has(obj.asset):
        return None
    return registry.make(obj.asset, obj.variant).bounds() * scale


def object_footprint(scene: Scene | None, obj: ObjectInstance) -> np.ndarray | None:
    """Corners of the object's footprint in the world, or ``None`` if its size is unknown."""
    b = asset_local_bounds(scene, obj)
    if b is None:
        return None
    return rect_corners(obj.position, (b[0, 0], b[0, 1], b[1, 0], b[1, 1]), yaw_of(obj))
