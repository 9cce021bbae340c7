"""Shared pieces of the built-in library: palettes, part builders, doors and drawers, and the
asset-frame fix-up.

A factory draws all of its randomness from the generator it is given, builds its parts in
whatever frame is convenient, and hands them to :func:`finish`, which moves everything into
the asset frame (footprint centred on the origin, lowest point on z = 0) together with the
receptacles that sit on the base. Links other than the base keep their parts in their own
frame, so only their origin moves.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from functools import lru_cache

import numpy as np

from legent_gym.world.assets import registry
from legent_gym.world.assets.model import (
    AssetModel,
    Collision,
    Joint,
    Link,
    Part,
    Receptacle,
    box_between,
    cylinder_part,
)

RGBA = tuple[float, float, float, float]
Palette = Sequence[tuple[float, float, float]]
#: The palette constants below: tuples, so that they concatenate (``WOODS + METALS[:1]``).
Colours = tuple[tuple[float, float, float], ...]

#: Style hints the library uses for ``Part.material``.
MATERIALS = frozenset({"wood", "fabric", "metal", "plastic", "ceramic", "glass", "food", "paper",
                       "leather", "plain"})
#: Room types an asset may name in ``rooms``.
ROOM_TYPES = frozenset({"bedroom", "living_room", "kitchen", "bathroom", "dining_room", "office",
                        "hallway"})
#: How far a hinged door opens (radians): a little past 90 degrees.
DOOR_RANGE = (0.0, 1.75)

# ---------------------------------------------------------------------------------------
# Palettes (linear-ish sRGB in 0..1). Each factory picks from these, with a little jitter,
# so two variants rarely share an exact colour.

WOODS: Colours = (
    (0.76, 0.60, 0.42),  # oak
    (0.45, 0.30, 0.19),  # walnut
    (0.55, 0.27, 0.17),  # cherry
    (0.85, 0.72, 0.52),  # maple
    (0.82, 0.66, 0.45),  # pine
    (0.27, 0.19, 0.14),  # espresso
    (0.62, 0.58, 0.52),  # grey-washed
    (0.92, 0.91, 0.88),  # white painted
)
FABRICS: Colours = (
    (0.55, 0.56, 0.58),  # grey
    (0.28, 0.29, 0.31),  # charcoal
    (0.80, 0.74, 0.62),  # beige
    (0.18, 0.24, 0.40),  # navy
    (0.20, 0.45, 0.47),  # teal
    (0.78, 0.60, 0.22),  # mustard
    (0.52, 0.60, 0.48),  # sage
    (0.70, 0.38, 0.28),  # terracotta
    (0.90, 0.87, 0.78),  # cream
    (0.33, 0.45, 0.62),  # denim blue
)
LEATHERS: Colours = (
    (0.42, 0.25, 0.15),  # brown
    (0.65, 0.45, 0.28),  # tan
    (0.12, 0.11, 0.11),  # black
    (0.40, 0.13, 0.12),  # oxblood
)
WICKERS: Colours = (
    (0.78, 0.62, 0.40),  # natural rattan
    (0.62, 0.45, 0.27),  # honey willow
    (0.42, 0.29, 0.18),  # dark willow
    (0.70, 0.66, 0.58),  # grey-washed
    (0.88, 0.85, 0.78),  # white-washed
)
BEDDING: Colours = (
    (0.95, 0.95, 0.93),  # white
    (0.74, 0.82, 0.90),  # light blue
    (0.70, 0.71, 0.72),  # light grey
    (0.66, 0.74, 0.64),  # sage
    (0.90, 0.76, 0.76),  # blush
    (0.22, 0.27, 0.42),  # navy
    (0.88, 0.82, 0.68),  # sand
)
METALS: Colours = (
    (0.72, 0.73, 0.75),  # brushed steel
    (0.85, 0.86, 0.88),  # chrome
    (0.25, 0.25, 0.27),  # gunmetal
    (0.10, 0.10, 0.11),  # black powder coat
    (0.78, 0.64, 0.35),  # brass
)
APPLIANCES: Colours = (
    (0.94, 0.94, 0.93),  # white
    (0.76, 0.77, 0.78),  # stainless
    (0.16, 0.16, 0.17),  # black
    (0.86, 0.84, 0.78),  # cream
)
COUNTERTOPS: Colours = (
    (0.92, 0.91, 0.89),  # white quartz
    (0.20, 0.20, 0.21),  # dark granite
    (0.60, 0.60, 0.60),  # concrete grey
    (0.80, 0.76, 0.70),  # travertine
)
CERAMICS: Colours = (
    (0.95, 0.95, 0.93),  # white
    (0.90, 0.86, 0.76),  # cream
    (0.60, 0.72, 0.82),  # pale blue
    (0.58, 0.66, 0.55),  # sage
    (0.74, 0.42, 0.30),  # terracotta
    (0.25, 0.26, 0.28),  # charcoal
    (0.92, 0.80, 0.35),  # yellow
)
BRIGHT_PLASTICS: Colours = (
    (0.85, 0.15, 0.15),  # red
    (0.15, 0.35, 0.80),  # blue
    (0.20, 0.65, 0.30),  # green
    (0.95, 0.80, 0.15),  # yellow
    (0.95, 0.50, 0.10),  # orange
    (0.55, 0.30, 0.70),  # purple
    (0.95, 0.55, 0.70),  # pink
)
DARK_PLASTICS: Colours = (
    (0.08, 0.08, 0.09),  # black
    (0.22, 0.22, 0.24),  # dark grey
    (0.55, 0.56, 0.58),  # silver grey
    (0.92, 0.92, 0.91),  # white
)
GLASSES: Colours = (
    (0.78, 0.86, 0.86),  # clear (tinted so it shows)
    (0.25, 0.45, 0.25),  # green
    (0.45, 0.28, 0.12),  # amber
    (0.62, 0.74, 0.88),  # blue
)
FOLIAGE: Colours = (
    (0.22, 0.45, 0.20),
    (0.30, 0.55, 0.25),
    (0.16, 0.36, 0.18),
    (0.40, 0.58, 0.30),
)
SCREEN: RGBA = (0.03, 0.03, 0.04, 1.0)
WHITE: RGBA = (0.95, 0.95, 0.94, 1.0)


def pick(rng: np.random.Generator, palette: Palette, jitter: float = 0.06) -> RGBA:
    """A palette colour with a small brightness jitter."""
    # Plain floats, not a numpy array: the same IEEE arithmetic at a fraction of the cost
    # (factories pick thousands of colours while houses are generated).
    r, g, b = palette[int(rng.integers(len(palette)))]
    f = 1.0 + rng.uniform(-jitter, jitter)
    return (_unit(float(r) * f), _unit(float(g) * f), _unit(float(b) * f), 1.0)


def _unit(c: float) -> float:
    """``c`` clipped to [0, 1] (as np.clip does for finite values)."""
    return 0.0 if c < 0.0 else (1.0 if c > 1.0 else c)


def shade(rgba: RGBA, factor: float) -> RGBA:
    """A darker (< 1) or lighter (> 1) version of a colour, e.g. for trim or handles."""
    f = float(factor)
    return (_unit(float(rgba[0]) * f), _unit(float(rgba[1]) * f), _unit(float(rgba[2]) * f), rgba[3])


def wood_or_metal(rng: np.random.Generator, p_wood: float) -> tuple[RGBA, str]:
    """A frame's colour and material: a wood with probability ``p_wood``, else a metal."""
    return (pick(rng, WOODS), "wood") if rng.random() < p_wood else (pick(rng, METALS), "metal")


def upholstery(rng: np.random.Generator, p_leather: float) -> tuple[RGBA, str]:
    """A cover's colour and material: a leather with probability ``p_leather``, else a fabric."""
    return (pick(rng, LEATHERS), "leather") if rng.random() < p_leather else (pick(rng, FABRICS), "fabric")


# ---------------------------------------------------------------------------------------
# Part builders.


def block(lo, hi, rgba: RGBA, material: str, *, collision: Collision = "box") -> Part:
    """The axis-aligned box spanning corners ``lo`` .. ``hi`` (12 triangles)."""
    return box_between(lo, hi, rgba, collision=collision, material=material)


def rod(x: float, y: float, z0: float, z1: float, radius: float, rgba: RGBA, material: str, *,
        segments: int = 8, radius_top: float | None = None, collision: Collision = "hull") -> Part:
    """A vertical cylinder (or cone frustum) standing from ``z0`` to ``z1`` at (x, y)."""
    return cylinder_part((x, y, (z0 + z1) / 2), radius, z1 - z0, rgba, segments=segments,
                         collision=collision, material=material, radius_top=radius_top)


def legs(x0: float, x1: float, y0: float, y1: float, z0: float, z1: float, size: float,
         rgba: RGBA, material: str, *, round_legs: bool = False) -> list[Part]:
    """Four legs in the corners of the rectangle x0..x1, y0..y1, outer faces flush with it."""
    parts = []
    for x in (x0 + size / 2, x1 - size / 2):
        for y in (y0 + size / 2, y1 - size / 2):
            if round_legs:
                parts.append(rod(x, y, z0, z1, size / 2, rgba, material))
            else:
                parts.append(block((x - size / 2, y - size / 2, z0), (x + size / 2, y + size / 2, z1),
                                   rgba, material))
    return parts


def lathe(profile: Sequence[tuple[float, float]], rgba: RGBA, material: str, *,
          segments: int = 10, center=(0.0, 0.0, 0.0), scale_xy=(1.0, 1.0),
          collision: Collision = "hull") -> Part:
    """A closed surface of revolution about z from a profile of (radius, z) points.

    The profile runs from the bottom up the outside (and, for a vessel, back down the
    inside); a point with radius 0 is a pole, and an open end is capped with a flat disc,
    the first facing down and the last facing up, so the surface is always closed.
    """
    ring = _lathe_ring(segments, float(scale_xy[0]), float(scale_xy[1]))
    verts: list[np.ndarray] = []
    for r, z in profile:
        if r > 1e-9:
            verts.append(np.column_stack([ring * r, np.full(segments, z)]))
        else:
            verts.append(np.array([[0.0, 0.0, z]]))
    if profile[0][0] > 1e-9:
        verts.append(np.array([[0.0, 0.0, profile[0][1]]]))
    if profile[-1][0] > 1e-9:
        verts.append(np.array([[0.0, 0.0, profile[-1][1]]]))
    v = np.concatenate(verts) + np.asarray(center, dtype=np.float64)
    faces = _lathe_faces(segments, tuple(r > 1e-9 for r, _ in profile))
    return Part.exact(v, faces.copy(), rgba, collision, material=material)


@lru_cache(maxsize=256)
def _lathe_ring(segments: int, sx: float, sy: float) -> np.ndarray:
    ang = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    ring = np.stack([np.cos(ang) * sx, np.sin(ang) * sy], axis=1)
    ring.flags.writeable = False
    return ring


@lru_cache(maxsize=256)
def _lathe_faces(segments: int, round_points: tuple[bool, ...]) -> np.ndarray:
    """Faces of a :func:`lathe` surface: they depend only on the segment count and on which
    profile points are rings (radius > 0) and which are poles."""
    rings: list[list[int]] = []  # vertex indices per profile point; one index for a pole
    start = 0
    for is_ring in round_points:
        if is_ring:
            rings.append(list(range(start, start + segments)))
            start += segments
        else:
            rings.append([start] * segments)
            start += 1
    faces: list[list[int]] = []
    for lower, upper in zip(rings[:-1], rings[1:]):
        for i in range(segments):
            j = (i + 1) % segments
            if lower[i] != lower[j]:
                faces.append([lower[i], lower[j], upper[j]])
            if upper[i] != upper[j]:
                faces.append([lower[i], upper[j], upper[i]])
    n = start
    if round_points[0]:
        faces += [[n, rings[0][(i + 1) % segments], rings[0][i]] for i in range(segments)]
        n += 1
    if round_points[-1]:
        faces += [[n, rings[-1][i], rings[-1][(i + 1) % segments]] for i in range(segments)]
    out = np.array(faces, dtype=np.int32)
    out.flags.writeable = False
    return out


def transformed(part: Part, *, rotate_x: float = 0.0, rotate_y: float = 0.0,
                pivot=(0.0, 0.0, 0.0), offset=(0.0, 0.0, 0.0)) -> Part:
    """``part`` rotated (radians, about x then y, around ``pivot``) and then moved by ``offset``."""
    cx, sx = np.cos(rotate_x), np.sin(rotate_x)
    cy, sy = np.cos(rotate_y), np.sin(rotate_y)
    rot = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]]) @ np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    p = np.asarray(pivot, dtype=np.float64)
    mat = np.eye(4)
    mat[:3, :3] = rot
    mat[:3, 3] = p - rot @ p + np.asarray(offset, dtype=np.float64)
    return part.transformed(mat)


def flatten_bottom(part: Part, depth: float) -> Part:
    """Slice a round part flat ``depth`` above its lowest point, so it rests without rolling."""
    v = part.vertices.copy()
    floor = v[:, 2].min() + depth
    v[:, 2] = np.maximum(v[:, 2], floor)
    return Part.exact(v, part.faces.copy(), part.rgba, part.collision, material=part.material)


def along_x(part: Part) -> Part:
    """``part`` turned so that its z axis runs along x (its x along y, its y up): a cyclic
    swap of the axes, a proper rotation, so the faces keep facing outward."""
    v = np.ascontiguousarray(part.vertices[:, [2, 0, 1]])
    return Part.exact(v, part.faces.copy(), part.rgba, part.collision, material=part.material)


def along_y(part: Part) -> Part:
    """``part`` turned so that its z axis runs along y (its x up, its y along x)."""
    v = np.ascontiguousarray(part.vertices[:, [1, 2, 0]])
    return Part.exact(v, part.faces.copy(), part.rgba, part.collision, material=part.material)


def annulus(outer: tuple[float, float], inner: tuple[float, float], z0: float, z1: float, rgba: RGBA,
            material: str, *, centre: tuple[float, float] = (0.0, 0.0), segments: int = 8,
            collision: Collision = "hull") -> Part:
    """A flat ring with a hole through it (a finger loop, a paper roll, a footrest) from ``z0``
    to ``z1``, with elliptical outer and inner semi-axes (x, y): a :func:`lathe` always caps
    its ends, so it cannot leave the hole open."""
    ang = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    c, s = np.cos(ang), np.sin(ang)
    rings = [np.column_stack([centre[0] + ax * c, centre[1] + ay * s, np.full(segments, z)])
             for (ax, ay) in (outer, inner) for z in (z0, z1)]
    return Part.exact(np.concatenate(rings), _annulus_faces(segments).copy(), rgba, collision,
                      material=material)


@lru_cache(maxsize=16)
def _annulus_faces(n: int) -> np.ndarray:
    """Faces of :func:`annulus`: rings outer-bottom, outer-top, inner-bottom, inner-top."""
    faces = []
    for i in range(n):
        j = (i + 1) % n
        ob, ot, ib, it = (0, i, j), (n, n + i, n + j), (2 * n, 2 * n + i, 2 * n + j), (3 * n, 3 * n + i, 3 * n + j)
        faces += [[ob[1], ob[2], ot[2]], [ob[1], ot[2], ot[1]],  # outer wall, facing out
                  [ib[1], it[2], ib[2]], [ib[1], it[1], it[2]],  # inner wall, facing the hole
                  [ot[1], ot[2], it[2]], [ot[1], it[2], it[1]],  # top
                  [ob[1], ib[2], ob[2]], [ob[1], ib[1], ib[2]]]  # bottom
    out = np.array(faces, dtype=np.int32)
    out.flags.writeable = False
    return out


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (N, 3) arrays: np.cross's arithmetic without its
    general-axis overhead."""
    out = np.empty_like(a)
    out[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    out[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    out[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return out


def volume(parts: Iterable[Part]) -> float:
    """Enclosed volume (m^3) of closed, outward-facing parts, by the divergence theorem."""
    parts = list(parts)
    if not parts:
        return 0.0
    # Every triangle's term at once (row by row the same arithmetic), then each part's sum
    # on its own, added up part by part as before.
    firsts = np.cumsum([0] + [len(p.vertices) for p in parts[:-1]]).astype(np.int32)
    tri = np.concatenate([p.vertices for p in parts])[np.concatenate([p.faces + k for p, k in zip(parts, firsts)])]
    rows = np.einsum("ij,ij->i", tri[:, 0], _cross(tri[:, 1], tri[:, 2]))
    total, start = 0.0, 0
    for p in parts:
        total += float(rows[start:start + len(p.faces)].sum()) / 6.0
        start += len(p.faces)
    return total


# ---------------------------------------------------------------------------------------
# Doors and drawers: links that move, closed at joint value 0.

#: Makes the handle of a door or drawer: its parts, given the point (x, y, z) on the front
#: face where the handle is centred and the height of the front.
Handle = Callable[[float, float, float, float], list[Part]]


def hinged_door(name: str, x0: float, x1: float, y_front: float, z0: float, z1: float, *, hinge_left: bool,
                rgba: RGBA, material: str, handle: Handle, thickness: float = 0.02,
                handle_z: float | None = None, handle_inset: float = 0.05, glass: RGBA | None = None,
                panel: RGBA | None = None, hinge_at_front: bool = False) -> Link:
    """A door covering x0..x1, z0..z1 in front of the plane ``y_front`` (with ``hinge_at_front``,
    behind it: its front face in that plane), hinged on one vertical edge, with the ``handle``
    parts ``handle_inset`` in from its free edge at ``handle_z`` (by default half way up).

    The door is a slab; with ``glass``, a frame of four stiles and rails round a pane of that
    colour; with ``panel``, a slab with a raised centre panel of that colour (a shaker door).
    The link origin is on the hinge axis; the left-hinged door turns about +z and the
    right-hinged one about -z, so both open toward +y with positive joint values.

    The axis runs along the door's back edge, or with ``hinge_at_front`` along its front edge:
    such a door never sweeps past the line of its hinge edge, so it may hang a few millimetres
    from a neighbour's edge (a row of doors).
    """
    width, t = x1 - x0, thickness
    y0 = -t if hinge_at_front else 0.0  # the door's back face in the link frame
    xa, xb = (0.0, width) if hinge_left else (-width, 0.0)
    free = width - handle_inset if hinge_left else -width + handle_inset
    if glass is None:
        parts = [block((xa, y0, z0), (xb, y0 + t, z1), rgba, material)]
    else:
        f = min(0.07, 0.2 * width)
        parts = [block((xa, y0, z0), (xa + f, y0 + t, z1), rgba, material),
                 block((xb - f, y0, z0), (xb, y0 + t, z1), rgba, material),
                 block((xa + f, y0, z0), (xb - f, y0 + t, z0 + f), rgba, material),
                 block((xa + f, y0, z1 - f), (xb - f, y0 + t, z1), rgba, material),
                 block((xa + f, y0 + 0.3 * t, z0 + f), (xb - f, y0 + 0.6 * t, z1 - f), glass, "glass")]
    if panel is not None:
        m = min(0.07, 0.15 * width)
        parts.append(block((xa + m, y0 + t, z0 + m), (xb - m, y0 + t + 0.006, z1 - m), panel, material,
                           collision="none"))
    parts += handle(free, y0 + t, (z0 + z1) / 2 if handle_z is None else handle_z, z1 - z0)
    pos = (x0 if hinge_left else x1, y_front, 0.0)
    axis = (0.0, 0.0, 1.0) if hinge_left else (0.0, 0.0, -1.0)
    return Link(name, parts, pos, Joint("hinge", axis, DOOR_RANGE))


def door_hinges(n: int) -> list[bool]:
    """Which of ``n`` doors side by side (left to right) hinge on their left edge: the left
    half and a middle one, so that no two hinges meet at one seam (two doors hinged there
    would swing into each other)."""
    return [i < (n + 1) // 2 for i in range(n)]


def drawer(name: str, x0: float, x1: float, y_front: float, depth: float, z0: float, z1: float, *,
           front: RGBA, body: RGBA, material: str, handle: Handle, handle_at: float = 0.5,
           side_clear: float = 0.008) -> tuple[Link, Receptacle]:
    """An open-topped drawer filling the slot x0..x1, z0..z1 behind the plane ``y_front``, with
    the ``handle`` parts centred on its front at ``handle_at`` of the slot's height.

    The box is ``side_clear`` narrower than the front on each side (more where the front
    overlays the carcass sides). The link origin is the slot's front-bottom centre. The
    receptacle is the drawer's inner bottom, in the drawer's frame, with the inner height as
    clearance.
    """
    gap, front_t, wall = 0.003, 0.02, 0.012
    hw = (x1 - x0) / 2 - gap
    h = z1 - z0
    bw = hw - side_clear  # the box runs clear of the carcass sides
    bottom = (gap + 0.006, gap + 0.006 + wall)
    side_top = gap + 0.75 * h
    back = -depth + wall
    parts = [
        block((-hw, -front_t, gap), (hw, 0.0, h - gap), front, material),
        block((-bw, -depth, bottom[0]), (bw, -front_t, bottom[1]), body, material),
        block((-bw, -depth, bottom[1]), (-bw + wall, -front_t, side_top), body, material),
        block((bw - wall, -depth, bottom[1]), (bw, -front_t, side_top), body, material),
        block((-bw + wall, -depth, bottom[1]), (bw - wall, back, side_top), body, material),
        *handle(0.0, 0.0, h * handle_at, h),
    ]
    inner = top_receptacle(name, (-bw + wall, back, 0.0), (bw - wall, -front_t, bottom[1]),
                           link=name, clearance=side_top - bottom[1])
    link = Link(name, parts, ((x0 + x1) / 2, y_front, z0), Joint("slide", (0.0, 1.0, 0.0), (0.0, 0.8 * depth)))
    return link, inner


# ---------------------------------------------------------------------------------------
# Annotations and the asset frame.


def top_receptacle(name: str, lo, hi, *, inset: float = 0.03, link: str = "base",
                   clearance: float = 1.0) -> Receptacle:
    """The rectangle on the top face of the box ``lo`` .. ``hi``, ``inset`` from its edges."""
    (x0, y0, _), (x1, y1, z1) = (tuple(float(c) for c in corner) for corner in (lo, hi))
    return Receptacle(name, ((x0 + x1) / 2, (y0 + y1) / 2),
                      ((x1 - x0) / 2 - inset, (y1 - y0) / 2 - inset), z1, link, float(clearance))


def round_top(name: str, radius: float, segments: int, height: float, *, inset: float = 0.02,
              center: tuple[float, float] = (0.0, 0.0), clearance: float = 1.0) -> Receptacle:
    """The square inside a round top of ``segments`` sides and ``radius`` centred on ``center``,
    ``inset`` from its edge."""
    half = radius * np.cos(np.pi / segments) / np.sqrt(2) - inset
    return Receptacle(name, center, (float(half), float(half)), float(height), "base", float(clearance))


def _xyz(point: np.ndarray) -> tuple[float, float, float]:
    """A 3-vector as a tuple of plain floats."""
    x, y, z = (float(c) for c in point)
    return x, y, z


_IDENTITY = np.eye(4)
_IDENTITY.flags.writeable = False


def _transformed_parts(parts: list[Part], vertices: np.ndarray, matrix: np.ndarray) -> list[Part]:
    """``[p.transformed(matrix) for p in parts]`` for a proper (det > 0) transform, in one
    matrix product over ``vertices`` (the parts' vertices concatenated): row by row the
    same arithmetic."""
    moved = vertices @ matrix[:3, :3].T + matrix[:3, 3]
    out, start = [], 0
    for p in parts:
        n = len(p.vertices)
        out.append(Part.exact(moved[start:start + n], p.faces.copy(), p.rgba, p.collision, p.uv, p.texture,
                              p.material))
        start += n
    return out


def finish(asset_id: str, base: list[Part], *, moving: Sequence[Link] = (),
           receptacles: Sequence[Receptacle] = (), **annotations) -> AssetModel:
    """Assemble the model and move it into the asset frame.

    ``base`` parts and base receptacles are shifted; moving links (doors, drawers) keep
    their parts and receptacles in their own frame and only their origin is shifted.
    """
    # One array per link rather than per part: the same sums, far fewer numpy calls.
    base_v = np.concatenate([p.vertices for p in base]) if base else np.zeros((0, 3))
    # (+ 0.0 as the base link's origin was added before: -0.0 becomes 0.0, as it did.)
    pts = np.concatenate([base_v + 0.0] + [np.concatenate([p.vertices for p in m.parts]) + np.asarray(m.pos)
                                     for m in moving if m.parts])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    shift = np.array([-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]])
    move = _IDENTITY.copy()
    move[:3, 3] = shift
    out = [Link("base", _transformed_parts(base, base_v, move))]
    out += [Link(m.name, m.parts, _xyz(np.asarray(m.pos) + shift), m.joint)
            for m in moving]
    recs = [r if r.link != "base" else
            Receptacle(r.name, (float(r.center[0] + shift[0]), float(r.center[1] + shift[1])),
                       (float(r.half_size[0]), float(r.half_size[1])), float(r.height + shift[2]),
                       r.link, float(r.clearance))
            for r in receptacles]
    return AssetModel(asset_id, asset_id, out, receptacles=recs, **annotations)


def small_object(asset_id: str, parts: list[Part], names: list[str],
                 density: float | Mapping[str, float] | Sequence[float], rooms: list[str]) -> AssetModel:
    """A pickupable asset standing on surfaces, whose mass is its solid volume (m^3) times
    ``density`` (kg/m^3): one for the whole object, one per material name (steel blades and
    plastic handles), or one per part. Decorative parts (collision "none") overlap the body,
    so they do not count."""
    if isinstance(density, Mapping):
        mass = sum(volume([p]) * density[p.material] for p in parts if p.collision != "none")
    elif isinstance(density, Sequence):
        mass = sum(volume([p]) * d for p, d in zip(parts, density, strict=True) if p.collision != "none")
    else:
        mass = volume(p for p in parts if p.collision != "none") * density
    return finish(asset_id, parts, names=list(names), rooms=list(rooms), pickupable=True,
                  placement="surface", mass=round(mass, 4), front_clearance=0.0)


def register_builtins(factories: Mapping[str, Callable[[np.random.Generator], AssetModel]]) -> None:
    """Register a library module's factories as built-in assets (each id's variants drawn
    from its own seed table: :mod:`legent_gym.world.assets.registry`)."""
    for asset_id, factory in factories.items():
        registry.register(asset_id, factory, builtin=True)
