"""Built-in wall decor (parametric, seeded, low-poly; registered on import): pictures that
hang on walls.

A wall picture is a painting, a print or a poster: a frame (wood or metal; none for a
poster) round a canvas that shows a landscape (sky, hills, a sun or moon) or an abstract
of coloured blocks. Its placement is ``hanging``: the house generator hangs it on a free
stretch of wall at eye level, above what stands there (:mod:`legent_gym.world.generation.furnish`),
and nothing collides with it (its parts have no collision shape): it blocks no floor and
holds nothing. The conventions are those of :mod:`legent_gym.world.assets.library.furniture`:
the back against the wall at y = 0 before :func:`finish` centres it, the front facing +y.
"""

from __future__ import annotations

import numpy as np

from legent_gym.world.assets.library.common import (
    METALS,
    RGBA,
    WOODS,
    Colours,
    block,
    finish,
    pick,
    register_builtins,
    shade,
)
from legent_gym.world.assets.model import AssetModel, Part, mesh_part

#: Canvas grounds and paint colours.
SKIES: Colours = ((0.55, 0.72, 0.9), (0.85, 0.78, 0.7), (0.95, 0.7, 0.45), (0.3, 0.35, 0.55), (0.8, 0.85, 0.88))
HILLS: Colours = ((0.35, 0.52, 0.3), (0.5, 0.6, 0.35), (0.45, 0.4, 0.55), (0.3, 0.4, 0.5), (0.62, 0.55, 0.4))
PAINTS: Colours = ((0.85, 0.25, 0.2), (0.95, 0.75, 0.2), (0.2, 0.4, 0.75), (0.15, 0.15, 0.18), (0.9, 0.9, 0.86),
                   (0.3, 0.6, 0.55), (0.85, 0.5, 0.6), (0.55, 0.35, 0.25))
#: Frames that are not wooden: metals, black, white and gilt.
OTHER_FRAMES: Colours = METALS[1:4] + ((0.08, 0.08, 0.08), (0.92, 0.9, 0.86), (0.75, 0.6, 0.3))
#: A canvas's depth in front of its ground: each layer a little further out, so none is hidden.
LAYER = 0.0015


#: A triangular prism's faces: the back triangle (0, 1, 2), the front one (3, 4, 5), and the
#: three sides, each turned outward by :func:`_hill`.
_PRISM_FACES = np.array([[0, 1, 2], [3, 4, 5], [0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4], [2, 0, 3], [2, 3, 5]])


def _hill(x0: float, x1: float, base: float, peak: float, peak_x: float, y: float, rgba: RGBA) -> Part:
    """A triangle of hill on the canvas, a layer thick (a closed prism) in front of plane y."""
    back = np.array([[x0, y, base], [x1, y, base], [peak_x, y, peak]])
    v = np.concatenate([back, back + [0.0, LAYER, 0.0]])
    faces = _PRISM_FACES.copy()
    # Each face turned away from the prism's centre (it is convex).
    tri = v[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    inward = np.einsum("ij,ij->i", normal, tri.mean(axis=1) - v.mean(axis=0)) < 0
    faces[inward] = faces[inward][:, ::-1]
    return mesh_part(v, faces, rgba, collision="none", material="paper")


def _landscape(rng: np.random.Generator, x0: float, x1: float, z0: float, z1: float, y: float) -> list[Part]:
    sky, hill = pick(rng, SKIES, jitter=0.08), pick(rng, HILLS, jitter=0.08)
    horizon = z0 + (z1 - z0) * rng.uniform(0.3, 0.55)
    parts = [block((x0, y, z0), (x1, y + LAYER, z1), sky, "paper", collision="none"),
             block((x0, y + LAYER, z0), (x1, y + 2 * LAYER, horizon), hill, "paper", collision="none")]
    width = x1 - x0
    for k in range(int(rng.integers(1, 4))):
        cx = x0 + width * rng.uniform(0.1, 0.9)
        half = width * rng.uniform(0.2, 0.45)
        peak = horizon + (z1 - horizon) * rng.uniform(0.2, 0.7)
        parts.append(_hill(max(x0, cx - half), min(x1, cx + half), horizon - 0.001, peak, cx, y + (2 + k) * LAYER,
                           shade(hill, float(rng.uniform(0.7, 1.1)))))
    radius = min(width, z1 - z0) * rng.uniform(0.06, 0.11)
    sx, sz = x0 + width * rng.uniform(0.15, 0.85), z1 - (z1 - horizon) * rng.uniform(0.25, 0.45)
    sun = pick(rng, ((1.0, 0.95, 0.75), (0.98, 0.8, 0.4), (0.95, 0.95, 0.95)), jitter=0.03)
    parts.append(block((sx - radius, y + 6 * LAYER, sz - radius), (sx + radius, y + 7 * LAYER, sz + radius), sun,
                       "paper", collision="none"))
    return parts


def _abstract(rng: np.random.Generator, x0: float, x1: float, z0: float, z1: float, y: float) -> list[Part]:
    ground = pick(rng, ((0.93, 0.91, 0.86), (0.2, 0.2, 0.22), (0.85, 0.8, 0.7)), jitter=0.03)
    parts = [block((x0, y, z0), (x1, y + LAYER, z1), ground, "paper", collision="none")]
    w, h = x1 - x0, z1 - z0
    for k in range(int(rng.integers(2, 6))):
        bw, bh = w * rng.uniform(0.15, 0.6), h * rng.uniform(0.15, 0.6)
        bx, bz = x0 + rng.uniform(0, w - bw), z0 + rng.uniform(0, h - bh)
        parts.append(block((bx, y + (1 + k) * LAYER, bz), (bx + bw, y + (2 + k) * LAYER, bz + bh),
                           pick(rng, PAINTS, jitter=0.06), "paper", collision="none"))
    return parts


def make_wall_picture(rng: np.random.Generator) -> AssetModel:
    kind = ("painting", "print", "poster")[int(rng.integers(3))]
    landscape = rng.random() < 0.5
    width = float(rng.uniform(0.4, 1.2))
    height = width * float(rng.uniform(0.6, 0.85)) if rng.random() < 0.7 else width * float(rng.uniform(1.2, 1.4))
    height = min(height, 1.0)
    parts: list[Part] = []
    if kind == "poster":  # no frame: the sheet lies on the wall
        depth, border = 0.004, 0.0
        y = 0.001
    else:
        depth = float(rng.uniform(0.025, 0.05))
        border = float(rng.uniform(0.03, 0.07)) * (0.5 if kind == "print" else 1.0)
        wooden = rng.random() < 0.6
        frame = pick(rng, WOODS if wooden else OTHER_FRAMES, jitter=0.04)
        material = "wood" if wooden else "metal"
        hw = width / 2
        parts += [block((-hw, 0.0, 0.0), (hw, depth, border), frame, material, collision="none"),
                  block((-hw, 0.0, height - border), (hw, depth, height), frame, material, collision="none"),
                  block((-hw, 0.0, border), (-hw + border, depth, height - border), frame, material, collision="none"),
                  block((hw - border, 0.0, border), (hw, depth, height - border), frame, material, collision="none")]
        y = depth * 0.5
        if kind == "print":  # a white mat round the picture
            mat = pick(rng, ((0.96, 0.95, 0.92), (0.9, 0.88, 0.82)), jitter=0.02)
            parts.append(block((-hw + border, 0.0, border), (hw - border, y, height - border), mat, "paper",
                               collision="none"))
            y += LAYER
            border += min(width, height) * float(rng.uniform(0.06, 0.12))
    x0, x1, z0, z1 = -width / 2 + border, width / 2 - border, border, height - border
    canvas = _landscape if landscape else _abstract
    parts += canvas(rng, x0, x1, z0, z1, y)
    names = ["picture"] + {"painting": ["painting", "canvas", "wall art"],
                           "print": ["framed print", "print", "wall art"],
                           "poster": ["poster", "wall art"]}[kind]
    return finish("wall_picture", parts, names=names, rooms=["living_room", "bedroom", "dining_room", "office",
                                                               "hallway", "kitchen"],
                  placement="hanging", mass=2.0, front_clearance=0.0)


FACTORIES = {"wall_picture": make_wall_picture}
register_builtins(FACTORIES)
