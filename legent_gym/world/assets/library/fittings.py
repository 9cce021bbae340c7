"""Built-in fittings and set dressing (parametric, seeded, low-poly; registered on import):
books standing on shelves, rugs, a kitchen's wall cabinets and the hood over its stove,
curtains beside windows and cushions on sofas and armchairs.

None of them is placed by the furniture rules of a room: the house generator adds them once
a room is furnished (:mod:`legent_gym.world.generation.dressing`), where they belong to
something already there: a row of books on a bookshelf's shelf, a rug under a sofa's coffee
table, wall cabinets over a kitchen's counters.

* ``shelved_book``: an upright book (spine to the front, +y). Static and not pickupable:
  a shelf holds a row of them, so its category never names one object of a house, and the
  pickupable ``book`` of the tasks keeps its meaning.
* ``rug``: placement ``floor``: it lies flat on the floor (a scene object of kind
  ``covering``), people walk over it and nothing collides with it. The generator stretches
  a variant to the size of what it lies under (the object's ``scale``).
* ``wall_cabinet`` and ``range_hood``: placement ``hanging``, their backs against the wall
  above a counter or a stove; a run of wall cabinets shares one variant, each stretched to
  the width of the piece under it.
* ``curtain``: placement ``hanging``, a panel of folds under a rod, one each side of a window
  (a room's curtains share a variant), stretched to hang from above the window to below its
  sill. Nothing collides with it.
* ``cushion``: standing against the back of a seat; static and not pickupable (the
  pickupable ``pillow`` is the one the tasks name).

The conventions are those of :mod:`legent_gym.world.assets.library.furniture`: the front
faces +y, and :func:`finish` centres the footprint on the origin with the lowest point on z = 0.
"""

from __future__ import annotations

import numpy as np

from legent_gym.world.assets.library.common import (
    APPLIANCES,
    BRIGHT_PLASTICS,
    FABRICS,
    LEATHERS,
    METALS,
    WOODS,
    Colours,
    block,
    finish,
    lathe,
    pick,
    register_builtins,
    shade,
)
from legent_gym.world.assets.model import AssetModel, Part

#: Book cloth and paper covers, besides the bright plastics' colours.
COVERS: Colours = ((0.15, 0.2, 0.35), (0.1, 0.3, 0.2), (0.35, 0.1, 0.1), (0.1, 0.1, 0.1), (0.85, 0.82, 0.72),
                   (0.45, 0.35, 0.25), (0.6, 0.15, 0.2), (0.25, 0.4, 0.55), (0.9, 0.9, 0.88))
PAGES = (0.95, 0.93, 0.86, 1.0)
#: Rug grounds and pattern colours: wools, jute and the fabrics.
RUG_GROUNDS: Colours = FABRICS + ((0.62, 0.2, 0.18), (0.7, 0.62, 0.48), (0.2, 0.22, 0.3), (0.8, 0.78, 0.74))
RUG_PATTERNS: Colours = ((0.9, 0.86, 0.76), (0.15, 0.15, 0.18), (0.75, 0.5, 0.2), (0.3, 0.45, 0.6),
                         (0.6, 0.25, 0.2), (0.45, 0.55, 0.4))
#: Cabinet fronts: woods and painted colours.
CABINET_FRONTS: Colours = WOODS + ((0.55, 0.62, 0.58), (0.3, 0.36, 0.45), (0.85, 0.85, 0.82), (0.2, 0.2, 0.22))
#: Sheer and pale curtain cloths, besides the fabrics.
SHEERS: Colours = ((0.95, 0.95, 0.92), (0.9, 0.88, 0.8), (0.85, 0.87, 0.88))
#: How thick a rug is (metres): thin enough to walk over.
RUG_THICKNESS = (0.006, 0.012)


def make_shelved_book(rng: np.random.Generator) -> AssetModel:
    t, d, h = rng.uniform(0.015, 0.06), rng.uniform(0.13, 0.24), rng.uniform(0.15, 0.3)
    leather = rng.random() < 0.2
    cover = pick(rng, LEATHERS if leather else BRIGHT_PLASTICS + COVERS)
    material = "leather" if leather else "paper"
    c, hx, hy = 0.003, t / 2, d / 2
    inset = min(0.004, h * 0.02)
    parts = [block((-hx, -hy, 0.0), (-hx + c, hy, h), cover, material, collision="none"),
             block((hx - c, -hy, 0.0), (hx, hy, h), cover, material, collision="none"),
             block((-hx + c, hy - c, 0.0), (hx - c, hy, h), cover, material, collision="none"),
             # The pages, recessed a little from the top, back and bottom: the book's one
             # collision box (a static shape, against the things put beside it).
             block((-hx + c, -hy + inset, inset), (hx - c, hy - c, h - inset), PAGES, "paper")]
    if rng.random() < 0.6:  # a band across the spine (the title)
        z = h * rng.uniform(0.55, 0.8)
        band = shade(cover, 1.6) if sum(cover[:3]) < 1.2 else shade(cover, 0.5)
        parts.append(block((-hx + c, hy, z), (hx - c, hy + 0.001, z + h * rng.uniform(0.06, 0.12)), band,
                           material, collision="none"))
    return finish("shelved_book", parts, names=["shelved book", "book on a shelf"],
                  rooms=["living_room", "office", "bedroom", "dining_room", "hallway"], placement="surface",
                  mass=round(float(t * d * h * 700.0), 4), front_clearance=0.0, drawn_with_support=True)


def make_rug(rng: np.random.Generator) -> AssetModel:
    width, depth = rng.uniform(1.4, 2.6), rng.uniform(0.9, 1.8)
    thickness = rng.uniform(*RUG_THICKNESS)
    ground = pick(rng, RUG_GROUNDS, jitter=0.05)
    accent = pick(rng, RUG_PATTERNS, jitter=0.05)
    hw, hd = width / 2, depth / 2
    layer = 0.001  # each pattern layer a millimetre above the one under it, so none is hidden
    style = ("bordered", "striped", "medallion", "round")[int(rng.integers(4))]
    if style == "round":
        ground_part = lathe([(0.5, 0.0), (0.5, thickness)], ground, "fabric", segments=20,
                            scale_xy=(width, depth), collision="none")
        inner = lathe([(0.5, thickness), (0.5, thickness + layer)], accent, "fabric", segments=20,
                      scale_xy=(width * 0.7, depth * 0.7), collision="none")
        parts: list[Part] = [ground_part, inner]
        names = ["rug", "round rug", "carpet"]
    else:
        parts = [block((-hw, -hd, 0.0), (hw, hd, thickness), ground, "fabric", collision="none")]
        top = thickness + layer
        if style == "bordered":
            b = min(width, depth) * rng.uniform(0.06, 0.12)
            parts += [block((-hw + b * 0.3, -hd + b * 0.3, thickness), (hw - b * 0.3, -hd + b, top), accent,
                            "fabric", collision="none"),
                      block((-hw + b * 0.3, hd - b, thickness), (hw - b * 0.3, hd - b * 0.3, top), accent,
                            "fabric", collision="none"),
                      block((-hw + b * 0.3, -hd + b, thickness), (-hw + b, hd - b, top), accent, "fabric",
                            collision="none"),
                      block((hw - b, -hd + b, thickness), (hw - b * 0.3, hd - b, top), accent, "fabric",
                            collision="none")]
        elif style == "striped":
            n = int(rng.integers(2, 6))
            edges = np.linspace(-hw, hw, 2 * n + 2)
            for k in range(n):
                parts.append(block((edges[2 * k + 1], -hd, thickness), (edges[2 * k + 2], hd, top), accent,
                                   "fabric", collision="none"))
        else:  # a medallion in the middle of a plain field
            mw, md = width * rng.uniform(0.3, 0.5), depth * rng.uniform(0.3, 0.5)
            parts.append(block((-mw / 2, -md / 2, thickness), (mw / 2, md / 2, top), accent, "fabric",
                               collision="none"))
        names = ["rug", "carpet", "area rug"]
    return finish("rug", parts, names=names, rooms=["living_room", "bedroom", "dining_room", "office", "hallway"],
                  placement="floor", mass=round(float(width * depth * thickness * 300.0), 3), front_clearance=0.0)


def make_wall_cabinet(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.5, 1.0), rng.uniform(0.3, 0.36), rng.uniform(0.55, 0.8)
    body = pick(rng, CABINET_FRONTS, jitter=0.03)
    front = body if rng.random() < 0.7 else pick(rng, CABINET_FRONTS, jitter=0.03)
    material = "wood"
    handle = pick(rng, METALS)
    hw, hd = width / 2, depth / 2
    gap, t = 0.003, 0.018
    doors = 1 if width < 0.6 else 2
    glass = rng.random() < 0.2
    parts = [block((-hw, -hd, 0.0), (hw, hd - t, height), shade(body, 0.92), material)]
    edges = np.linspace(-hw, hw, doors + 1)
    knob_h = rng.uniform(0.08, 0.16)
    for k in range(doors):
        x0, x1 = edges[k] + gap, edges[k + 1] - gap
        parts.append(block((x0, hd - t, gap), (x1, hd, height - gap), front, material, collision="none"))
        if glass:
            parts.append(block((x0 + 0.06, hd, 0.06), (x1 - 0.06, hd + 0.001, height - 0.06),
                               (0.7, 0.8, 0.82, 1.0), "glass", collision="none"))
        # The pull at the bottom corner away from the hinge (cabinets hang above the eye).
        hx = x1 - 0.04 if (doors == 1 or k == 0) else x0 + 0.04
        parts.append(block((hx - 0.006, hd, 0.03), (hx + 0.006, hd + 0.02, 0.03 + knob_h), handle, "metal",
                           collision="none"))
    return finish("wall_cabinet", parts, names=["wall cabinet", "upper cabinet", "kitchen cabinet", "cupboard"],
                  rooms=["kitchen"], placement="hanging", mass=float(rng.uniform(12, 25)), front_clearance=0.0)


def make_range_hood(rng: np.random.Generator) -> AssetModel:
    width, depth = rng.uniform(0.6, 0.9), rng.uniform(0.42, 0.5)
    shell = pick(rng, METALS[:2] + APPLIANCES, jitter=0.02)
    hw, hd = width / 2, depth / 2
    canopy_h = rng.uniform(0.06, 0.14)
    parts = [block((-hw, -hd, 0.0), (hw, hd, canopy_h), shell, "metal")]
    if rng.random() < 0.65:  # a chimney up the wall
        cw, cd, ch = width * rng.uniform(0.3, 0.45), depth * rng.uniform(0.5, 0.65), rng.uniform(0.45, 0.7)
        parts.append(block((-cw / 2, -hd, canopy_h), (cw / 2, -hd + cd, canopy_h + ch), shell, "metal"))
        names = ["range hood", "cooker hood", "extractor hood", "chimney hood"]
    else:  # a slab under a cabinet line, with a visor
        parts.append(block((-hw, -hd, canopy_h), (hw, hd - 0.05, canopy_h + rng.uniform(0.15, 0.3)), shell, "metal"))
        names = ["range hood", "cooker hood", "extractor hood"]
    parts.append(block((-hw + 0.05, -hd + 0.05, -0.004), (hw - 0.05, hd - 0.05, 0.0), shade(shell, 0.6), "metal",
                       collision="none"))  # the filter grille underneath
    return finish("range_hood", parts, names=names, rooms=["kitchen"], placement="hanging",
                  mass=float(rng.uniform(8, 15)), front_clearance=0.0)


def make_curtain(rng: np.random.Generator) -> AssetModel:
    width, height = rng.uniform(0.3, 0.5), rng.uniform(1.3, 1.7)
    cloth = pick(rng, FABRICS + SHEERS, jitter=0.05)
    rod_c = pick(rng, METALS + WOODS[:2], jitter=0.03)
    folds = int(rng.integers(4, 7))
    depth = rng.uniform(0.02, 0.04)  # how far the folds stand out from one another
    edges = np.linspace(-width / 2, width / 2, folds + 1)
    overlap = 0.004  # neighbouring folds share a sliver, so no gap shows between them
    parts = []
    for k in range(folds):
        y0 = 0.0 if k % 2 == 0 else depth
        parts.append(block((edges[k] - overlap, y0, 0.0), (edges[k + 1] + overlap, y0 + 0.012, height),
                           cloth if k % 2 == 0 else shade(cloth, 0.88), "fabric", collision="none"))
    r = rng.uniform(0.008, 0.015)
    parts.append(block((-width / 2 - 0.04, depth / 2 - r, height - 0.01), (width / 2 + 0.04, depth / 2 + r,
                                                                          height - 0.01 + 2 * r),
                       rod_c, "metal" if rod_c in METALS else "wood", collision="none"))
    return finish("curtain", parts, names=["curtain", "drape", "drapes"],
                  rooms=["living_room", "bedroom", "dining_room", "office", "kitchen", "hallway", "bathroom"],
                  placement="hanging", mass=1.5, front_clearance=0.0)


def make_cushion(rng: np.random.Generator) -> AssetModel:
    width, height, t = rng.uniform(0.34, 0.52), rng.uniform(0.32, 0.5), rng.uniform(0.1, 0.16)
    cover = pick(rng, FABRICS + RUG_PATTERNS, jitter=0.06)
    hw, ht = width / 2, t / 2
    # A plump middle between thinner edges: three slabs, the middle one standing proud.
    parts = [block((-hw, -ht * 0.55, 0.0), (hw, ht * 0.55, height), cover, "fabric", collision="none"),
             block((-hw * 0.8, -ht, height * 0.1), (hw * 0.8, ht, height * 0.9), cover, "fabric")]
    if rng.random() < 0.5:  # a band or a square of another colour on its face
        accent = pick(rng, RUG_PATTERNS + FABRICS, jitter=0.05)
        if rng.random() < 0.5:
            z = height * rng.uniform(0.35, 0.55)
            parts.append(block((-hw * 0.8, ht, z), (hw * 0.8, ht + 0.001, z + height * 0.15), accent, "fabric",
                               collision="none"))
        else:
            parts.append(block((-hw * 0.45, ht, height * 0.3), (hw * 0.45, ht + 0.001, height * 0.7), accent,
                               "fabric", collision="none"))
    return finish("cushion", parts, names=["cushion", "throw cushion", "scatter cushion"],
                  rooms=["living_room", "bedroom", "office"], placement="surface",
                  mass=round(float(width * height * t * 60.0), 3), front_clearance=0.0,
                  drawn_with_support=True)


FACTORIES = {"shelved_book": make_shelved_book, "rug": make_rug, "wall_cabinet": make_wall_cabinet,
             "range_hood": make_range_hood, "curtain": make_curtain, "cushion": make_cushion}
register_builtins(FACTORIES)
