"""Built-in small objects of offices and bathrooms: stationery, devices and toiletries (pickupable, parametric, seeded, low-poly; registered on import).

The conventions are those of :mod:`legent_gym.world.assets.library.objects`.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache

import numpy as np

from legent_gym.world.assets.library.common import (
    BEDDING,
    BRIGHT_PLASTICS,
    CERAMICS,
    DARK_PLASTICS,
    FABRICS,
    METALS,
    RGBA,
    SCREEN,
    WOODS,
    along_x,
    annulus,
    block,
    lathe,
    pick,
    register_builtins,
    rod,
    shade,
    small_object,
    transformed,
)
from legent_gym.world.assets.model import AssetModel, Collision, Part, cylinder_part

OFFICE = ["office", "bedroom", "living_room"]
BATHROOM = ["bathroom"]
#: Covers of notebooks and barrels of pens: bright plastics and the darker office colours.
COVERS = BRIGHT_PLASTICS + ((0.15, 0.2, 0.35), (0.1, 0.3, 0.2), (0.35, 0.1, 0.1), (0.1, 0.1, 0.1),
                            (0.5, 0.36, 0.22))
PAPER = ((0.96, 0.95, 0.9), (0.98, 0.97, 0.94), (0.95, 0.92, 0.82))



# ---------------------------------------------------------------------------------------
# Part builders the shared ones lack: extruded outlines, turned ovals.


def _prism(outline: Sequence[tuple[float, float]], z0: float, z1: float, rgba: RGBA, material: str, *,
           collision: Collision = "hull") -> Part:
    """A convex counter-clockwise ``outline`` in the xy plane, extruded from ``z0`` to ``z1``."""
    xy = np.asarray(outline, dtype=np.float64)
    n = len(xy)
    v = np.concatenate([np.column_stack([xy, np.full(n, z0)]), np.column_stack([xy, np.full(n, z1)])])
    return Part.exact(v, _prism_faces(n).copy(), rgba, collision, material=material)


@lru_cache(maxsize=16)
def _prism_faces(n: int) -> np.ndarray:
    faces = []
    for i in range(n):
        j = (i + 1) % n
        faces += [[i, j, n + j], [i, n + j, n + i]]
    for i in range(1, n - 1):
        faces += [[0, i + 1, i], [n, n + i, n + i + 1]]
    out = np.array(faces, dtype=np.int32)
    out.flags.writeable = False
    return out


def _oval_lathe(profile: Sequence[tuple[float, float]], sy: float, rgba: RGBA, material: str, *,
                segments: int = 8, collision: Collision = "hull") -> Part:
    """A :func:`lathe` turned so that flat sides face the axes, then squashed by ``sy`` in y:
    a rounded-rectangle section (a bar of soap, a flat bottle). Radii are the half-widths
    across the flats along x."""
    k = 1.0 / np.cos(np.pi / segments)
    part = lathe([(r * k, z) for r, z in profile], rgba, material, segments=segments, collision=collision)
    a = np.pi / segments
    rot = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    v = part.vertices @ rot.T * np.array([1.0, sy, 1.0])
    return Part.exact(v, part.faces, part.rgba, part.collision, material=part.material)


def _chamfered(hx: float, hy: float, c: float) -> list[tuple[float, float]]:
    """A rectangle's outline (counter-clockwise) with its corners cut by ``c``."""
    return [(-hx + c, -hy), (hx - c, -hy), (hx, -hy + c), (hx, hy - c), (hx - c, hy), (-hx + c, hy),
            (-hx, hy - c), (-hx, -hy + c)]


# ---------------------------------------------------------------------------------------
# Stationery.


def make_pen(rng: np.random.Generator) -> AssetModel:
    length, tip = rng.uniform(0.14, 0.155), rng.uniform(0.012, 0.016)
    # A flattened hexagonal barrel, lying on one of its flats: a round or regular-hexagonal
    # barrel ~1 cm across has too narrow a face to lie on without rolling.
    half, bulge, h = rng.uniform(0.0058, 0.0063), rng.uniform(0.0008, 0.0012), rng.uniform(0.0095, 0.011)
    barrel = pick(rng, COVERS + DARK_PLASTICS[2:])
    trim = pick(rng, METALS[:3] + DARK_PLASTICS[:1])
    section = [(-half, 0.0), (half, 0.0), (half + bulge, h / 2), (half, h), (-half, h), (-half - bulge, h / 2)]
    body = along_x(_prism(section, tip, length, barrel, "plastic"))
    nose = 0.42 * h
    point = along_x(lathe([(0.0, 0.0), (0.25 * nose, 0.003), (nose, tip + 0.001)], trim, "metal", segments=6))
    point = transformed(point, offset=(0.0, 0.0, h / 2))
    parts = [body, point]
    if rng.random() < 0.5:
        # A cap over the point, a little wider than the barrel, with the clip on it.
        cap = pick(rng, COVERS)
        grow = 0.0006
        wide = [(x + (grow if x > 0 else -grow), z + (grow if z > h / 2 else -grow)) for x, z in section]
        parts.append(along_x(_prism(wide, -0.002, 0.05, cap, "plastic", collision="none")))
        clip_x, clip_z, clip = 0.012, h + grow, cap
    else:
        # A click button out of the back end.
        button = lathe([(0.3 * h, length - 0.002), (0.3 * h, length + 0.006)], trim, "plastic", segments=6,
                       collision="none")
        parts.append(transformed(along_x(button), offset=(0.0, 0.0, h / 2)))
        clip_x, clip_z, clip = length - 0.045, h, trim
    parts.append(block((clip_x, -0.0017, clip_z - 0.0005), (clip_x + 0.035, 0.0017, clip_z + 0.0022), clip,
                       "metal", collision="none"))
    # A hollow barrel round an ink refill.
    return small_object("pen", parts, ["pen", "ballpoint pen"], 550.0, OFFICE)


def make_notebook(rng: np.random.Generator) -> AssetModel:
    w = rng.uniform(0.09, 0.21)
    length, t = w * rng.uniform(1.35, 1.45), rng.uniform(0.005, 0.02)
    cover, pages = pick(rng, COVERS), pick(rng, PAPER, jitter=0.02)
    hw, hl = w / 2, length / 2
    if rng.random() < 0.5:
        # A spiral-bound pad: card back, pages flush with it, a thin cover, and the wire coil
        # along the left or the top edge.
        c, card = 0.0008, pick(rng, ((0.6, 0.55, 0.48), (0.45, 0.42, 0.4)))
        parts = [block((-hw, -hl, 0.0), (hw, hl, c), card, "paper"),
                 block((-hw, -hl, c), (hw, hl, t - c), pages, "paper"),
                 block((-hw, -hl, t - c), (hw, hl, t), cover, "paper")]
        coil = pick(rng, METALS[:2] + METALS[3:4])
        if rng.random() < 0.5:
            lo, hi = (-hw - 0.002, -hl + 0.005, 0.0), (-hw + 0.006, hl - 0.005, t + 0.002)
        else:
            lo, hi = (-hw + 0.005, -hl - 0.002, 0.0), (hw - 0.005, -hl + 0.006, t + 0.002)
        parts.append(block(lo, hi, coil, "metal", collision="none"))
    else:
        # A hardbound journal: boards and spine round the pages, often an elastic band.
        c = 0.002
        parts = [block((-hw, -hl, 0.0), (hw, hl, c), cover, "paper"),
                 block((-hw, -hl, t - c), (hw, hl, t), cover, "paper"),
                 block((-hw, -hl, c), (-hw + c, hl, t - c), cover, "paper"),
                 block((-hw + c, -hl + 0.002, c), (hw - 0.002, hl - 0.002, t - c), pages, "paper")]
        if rng.random() < 0.5:
            x = hw - 0.02
            parts.append(block((x, -hl - 0.0006, 0.0), (x + 0.006, hl + 0.0006, t + 0.0006), shade(cover, 0.5),
                               "fabric", collision="none"))
    return small_object("notebook", parts, ["notebook", "notepad"], 700.0, OFFICE)


def make_stapler(rng: np.random.Generator) -> AssetModel:
    length, w, top = rng.uniform(0.13, 0.19), rng.uniform(0.036, 0.05), rng.uniform(0.042, 0.062)
    arm_colour = pick(rng, BRIGHT_PLASTICS + DARK_PLASTICS[:3] + METALS[:2])
    base_colour = pick(rng, DARK_PLASTICS[:2])
    steel = pick(rng, METALS[:2], jitter=0.02)
    base_h = rng.uniform(0.008, 0.012)
    gap = base_h + rng.uniform(0.004, 0.008)  # underside of the arm, where the paper goes
    hl, hw, aw = length / 2, w / 2, 0.4 * w
    # The arm's side outline (x, z): a long box whose nose slopes down to the front (+x).
    side = [(-hl, gap), (hl - 0.006, gap), (hl, gap + 0.4 * (top - gap)), (hl - 0.035, top),
            (-hl + 0.012, top), (-hl, top - 0.01)]
    arm = transformed(_prism(side, -aw, aw, arm_colour, "metal"), rotate_x=np.pi / 2)
    parts = [block((-hl, -hw, 0.0), (hl, hw, base_h), base_colour, "plastic"),
             block((-hl + 0.004, -0.9 * aw, base_h), (-hl + 0.03, 0.9 * aw, gap + 0.003), base_colour, "plastic"),
             arm,
             block((hl - 0.03, -0.006, base_h), (hl - 0.01, 0.006, base_h + 0.0008), steel, "metal",
                   collision="none"),
             block((-hl + 0.02, -0.5 * aw, top), (hl - 0.045, 0.5 * aw, top + 0.0008), shade(arm_colour, 0.7),
                   "metal", collision="none")]
    # Sheet steel round a hollow magazine: far lighter than solid.
    return small_object("stapler", parts, ["stapler"], 800.0, ["office"])


def make_scissors(rng: np.random.Generator) -> AssetModel:
    blade, t = rng.uniform(0.09, 0.125), rng.uniform(0.002, 0.0028)
    shank = rng.uniform(0.024, 0.03)  # pivot to the finger loops
    steel = pick(rng, METALS[:3], jitter=0.03)
    grip = pick(rng, BRIGHT_PLASTICS + DARK_PLASTICS[:2])
    loop_t, wall = rng.uniform(0.005, 0.008), rng.uniform(0.0045, 0.0055)
    yl = rng.uniform(0.014, 0.018)  # the loops' centres either side of the blades
    ox, oy = rng.uniform(0.018, 0.024), rng.uniform(0.013, 0.016)
    big = rng.uniform(1.15, 1.45)  # the loop for the fingers is often the larger
    # One blade and its shank, closed over the other: tip at +x, shank back to the loop at -y.
    outline = [(-shank, -yl - 0.004), (blade, -0.0008), (blade - 0.006, 0.002), (0.0, 0.0085),
               (-shank, -yl + 0.004)]
    mirror = [(x, -y) for x, y in reversed(outline)]
    parts = [_prism(outline, 0.0, t, steel, "metal"),
             _prism(mirror, t, 2 * t, shade(steel, 0.92), "metal")]
    for sy, scale in ((-1, 1.0), (1, big)):
        ax, ay = ox * scale, oy * scale
        parts.append(annulus((ax, ay), (ax - wall, ay - wall), 0.0, loop_t, grip, "plastic",
                              centre=(-shank - ax + 0.7 * wall, sy * (yl + ay - oy)), segments=6))
    parts.append(rod(0.0, 0.0, 0.0, 2 * t + 0.001, 0.0025, shade(steel, 0.7), "metal", segments=6,
                     collision="none"))
    return small_object("scissors", parts, ["scissors", "pair of scissors"], {"metal": 7800.0, "plastic": 1100.0},
                  ["office", "kitchen", "living_room"])


# ---------------------------------------------------------------------------------------
# Devices.

#: Keyboard colours: (case, keys).
KEYBOARDS = (((0.08, 0.08, 0.09), (0.17, 0.17, 0.18)),
             ((0.24, 0.24, 0.26), (0.07, 0.07, 0.08)),
             ((0.72, 0.73, 0.75), (0.95, 0.95, 0.94)),
             ((0.93, 0.93, 0.92), (0.78, 0.79, 0.81)))


def make_keyboard(rng: np.random.Generator) -> AssetModel:
    full = rng.random() < 0.6  # with a number pad
    w = rng.uniform(0.42, 0.46) if full else rng.uniform(0.29, 0.36)
    d, front = rng.uniform(0.115, 0.15), rng.uniform(0.012, 0.016)
    back = front + rng.uniform(0.005, 0.012)  # a wedge, higher at the back (-y)
    case_rgb, keys_rgb = KEYBOARDS[int(rng.integers(len(KEYBOARDS)))]
    case, keys = pick(rng, (case_rgb,), jitter=0.05), pick(rng, (keys_rgb,), jitter=0.05)
    key_h, margin = rng.uniform(0.004, 0.006), rng.uniform(0.01, 0.016)
    hw, hd = w / 2, d / 2
    wedge = along_x(_prism([(-hd, 0.0), (hd, 0.0), (hd, front), (-hd, back)], -hw, hw, case, "plastic"))
    parts = [wedge]

    def surface(y: float) -> float:
        return front + (back - front) * (hd - y) / d

    def keys_block(x0: float, x1: float, y0: float, y1: float) -> Part:
        return block((x0, y0, surface(y1) - 0.001), (x1, y1, surface(y0) + key_h), keys, "plastic",
                     collision="none")

    rows = 6 if full else 5
    pitch, gap = (d - 2 * margin) / rows, 0.0025
    pad = 0.075 if full else 0.0
    # The typist sits at +y, so their left is +x and the number pad is at -x.
    x0, x1 = -hw + margin + (pad + 0.012 if full else 0.0), hw - margin
    span = x1 - x0
    for i in range(rows):  # row 0, the space bar's, nearest the typist
        y1 = hd - margin - i * pitch
        y0 = y1 - pitch + gap
        if i == 0:
            for a, b in ((0.0, 0.27), (0.285, 0.72), (0.735, 1.0)):  # from the typist's left
                parts.append(keys_block(x1 - b * span, x1 - a * span, y0, y1))
        else:
            parts.append(keys_block(x0, x1, y0, y1))
    if full:
        px0, px1 = -hw + margin, -hw + margin + pad
        mid = hd - margin - 2 * pitch
        parts += [keys_block(px0, px1, mid + gap, hd - margin),
                  keys_block(px0, px1, hd - margin - (rows - 1) * pitch + gap, mid)]
    # A plastic shell over a circuit board and key switches.
    return small_object("keyboard", parts, ["keyboard", "computer keyboard"], 500.0, ["office", "bedroom"])


def make_computer_mouse(rng: np.random.Generator) -> AssetModel:
    length, width, height = rng.uniform(0.095, 0.125), rng.uniform(0.055, 0.068), rng.uniform(0.032, 0.042)
    shell = pick(rng, DARK_PLASTICS + ((0.5, 0.07, 0.09), (0.15, 0.25, 0.45)))
    wheel_colour = pick(rng, ((0.1, 0.1, 0.11), (0.35, 0.36, 0.38)))
    r = length / 2
    rs = [0.93 * r, r, 0.84 * r, 0.48 * r, 0.0]
    zs = [0.0, 0.3 * height, 0.72 * height, 0.96 * height, height]
    body = lathe(list(zip(rs, zs)), shell, "plastic", segments=10, scale_xy=(width / length, 1.0))
    # The hump sits behind the middle, where the palm rests: shear the top toward the back.
    hump = rng.uniform(0.15, 0.3) * r
    v = body.vertices.copy()
    v[:, 1] -= hump * v[:, 2] / height
    parts = [Part.exact(v, body.faces, shell, "hull", material="plastic")]
    # The scroll wheel pokes out of the top surface a third of the way back from the front.
    front = [rho - hump * z / height for rho, z in zip(rs, zs)]
    yw = 0.35 * r
    zw = float(np.interp(yw, front[:0:-1], zs[:0:-1]))
    rw = 0.0065
    wheel = cylinder_part((0.0, yw, zw - 0.0025), rw, 0.006, wheel_colour, segments=8, collision="none",
                          material="plastic")
    parts.append(transformed(wheel, rotate_y=np.pi / 2, pivot=(0.0, yw, zw - 0.0025)))
    return small_object("computer_mouse", parts, ["mouse", "computer mouse"], 650.0, ["office", "bedroom"])


def make_tablet(rng: np.random.Generator) -> AssetModel:
    w = rng.uniform(0.13, 0.2)
    length, t = w * rng.uniform(1.32, 1.45), rng.uniform(0.006, 0.008)
    bezel = rng.uniform(0.007, 0.012)
    if rng.random() < 0.4:
        # In a protective case: thicker, coloured, with a lip round the glass.
        shell, material = pick(rng, COVERS[:9] + DARK_PLASTICS[:2]), "plastic"
        t += rng.uniform(0.003, 0.005)
        lip = 0.003
    else:
        shell = pick(rng, ((0.75, 0.76, 0.78), (0.3, 0.31, 0.33), (0.85, 0.75, 0.65), (0.6, 0.66, 0.74)),
                     jitter=0.03)
        material, lip = "metal", 0.0005
    face = pick(rng, ((0.08, 0.08, 0.09), (0.93, 0.93, 0.92)), jitter=0.03)
    hw, hl = w / 2, length / 2
    corner = rng.uniform(0.008, 0.014)
    parts = [_prism(_chamfered(hw, hl, corner), 0.0, t, shell, material),
             _prism(_chamfered(hw - lip, hl - lip, corner - 0.4 * lip), t, t + 0.0004, face, "glass",
                    collision="none"),
             block((-hw + bezel, -hl + bezel, t), (hw - bezel, hl - bezel, t + 0.0008), SCREEN, "glass",
                   collision="none"),
             block((-0.0015, hl - bezel / 2 - 0.0015, t), (0.0015, hl - bezel / 2 + 0.0015, t + 0.0008),
                   (0.02, 0.02, 0.03, 1.0), "glass", collision="none")]
    return small_object("tablet", parts, ["tablet", "ipad"], 1600.0, ["living_room", "bedroom", "office"])


# ---------------------------------------------------------------------------------------
# Toiletries.

SOAPS = ((0.95, 0.94, 0.9), (0.95, 0.82, 0.84), (0.8, 0.9, 0.74), (0.84, 0.8, 0.93), (0.95, 0.88, 0.66),
         (0.74, 0.87, 0.93), (0.88, 0.66, 0.45))


def make_soap(rng: np.random.Generator) -> AssetModel:
    length, w, t = rng.uniform(0.075, 0.1), rng.uniform(0.048, 0.062), rng.uniform(0.02, 0.032)
    colour = pick(rng, SOAPS, jitter=0.04)
    hx = length / 2
    bar_profile = [(0.9 * hx, 0.0), (hx, 0.3 * t), (hx, 0.7 * t), (0.88 * hx, t)]
    parts: list[Part] = []
    lift = 0.0
    if rng.random() < 0.5:
        # On a shallow dish, ceramic or bamboo.
        m, depth = rng.uniform(0.012, 0.02), rng.uniform(0.014, 0.02)
        dx, dy, floor = hx + m, w / 2 + m, 0.004
        if rng.random() < 0.6:
            dish, material = pick(rng, CERAMICS), "ceramic"
        else:
            dish, material = pick(rng, WOODS[:5]), "wood"
        parts.append(_oval_lathe([(dx - 0.006, 0.0), (dx, depth), (dx - 0.004, depth), (dx - 0.01, floor)],
                                 dy / dx, dish, material))
        lift = floor
    bar = _oval_lathe([(r, z + lift) for r, z in bar_profile], w / length, colour, "plain")
    return small_object("soap", [bar, *parts], ["soap", "bar of soap"],
                  {"plain": 1050.0, "ceramic": 2000.0, "wood": 700.0}, BATHROOM + ["kitchen"])


SHAMPOO_BOTTLES = BRIGHT_PLASTICS + ((0.95, 0.95, 0.94), (0.2, 0.5, 0.55), (0.1, 0.1, 0.12),
                                     (0.75, 0.85, 0.9), (0.9, 0.85, 0.7))
LABELS = ((0.95, 0.95, 0.93), (0.9, 0.86, 0.72), (0.15, 0.15, 0.17))


def make_shampoo(rng: np.random.Generator) -> AssetModel:
    h = rng.uniform(0.15, 0.22)
    if rng.random() < 0.3:
        hx, sy = rng.uniform(0.024, 0.03), 1.0  # a round bottle
    else:
        hx, sy = rng.uniform(0.03, 0.038), rng.uniform(0.5, 0.7)  # a flat oval one
    bottle = pick(rng, SHAMPOO_BOTTLES)
    cap = pick(rng, ((0.95, 0.95, 0.94), (0.1, 0.1, 0.11), (0.78, 0.79, 0.8))
               + (bottle[:3],), jitter=0.04)
    depth = hx * sy
    rc = min(max(0.012, rng.uniform(0.6, 0.9) * depth), 0.95 * depth)
    hc, neck = rng.uniform(0.016, 0.028), 0.8 * rc
    # Straight sides up to a short, rounded shoulder, the cap sitting right on it.
    s = rng.uniform(0.018, 0.03)
    shoulder = max(0.75 * hx, neck + 0.003)
    body = _oval_lathe([(0.92 * hx, 0.0), (hx, 0.012), (hx, h - s), (shoulder, h - 0.35 * s), (neck, h)], sy,
                       bottle, "plastic")
    label = _oval_lathe([(hx + 0.0006, 0.2 * h), (hx + 0.0006, 0.6 * h)], (hx * sy + 0.0006) / (hx + 0.0006),
                        pick(rng, LABELS, jitter=0.03), "paper", collision="none")
    parts = [body, label, rod(0.0, 0.0, h - 0.003, h + hc, rc, cap, "plastic", segments=8, radius_top=0.9 * rc)]
    # Full of a liquid about as dense as water.
    return small_object("shampoo", parts, ["shampoo", "shampoo bottle"], 1000.0, BATHROOM)


def make_towel(rng: np.random.Generator) -> AssetModel:
    length, w = rng.uniform(0.22, 0.34), rng.uniform(0.14, 0.25)
    layers, t = int(rng.integers(2, 5)), rng.uniform(0.008, 0.016)
    colour = pick(rng, FABRICS + BEDDING)
    parts = []
    x0 = x1 = 0.0
    for i in range(layers):
        # Folds are never quite square: each layer sits a few millimetres off the last.
        x0 = -length / 2 + rng.uniform(0.0, 0.006)
        x1 = length / 2 - rng.uniform(0.0, 0.006)
        z0, z1, c = i * t, (i + 1) * t, 0.4 * t  # rounded where the towel folds over
        outline = [(x0 + c, z0), (x1 - c, z0), (x1, z0 + c), (x1, z1 - c), (x1 - c, z1), (x0 + c, z1),
                   (x0, z1 - c), (x0, z0 + c)]
        parts.append(transformed(_prism(outline, -w / 2, w / 2, colour, "fabric"), rotate_x=np.pi / 2))
    if rng.random() < 0.5:
        # A woven stripe across the top fold, near one end.
        top = layers * t
        y = w / 2 - rng.uniform(0.02, 0.04)
        stripe = pick(rng, ((0.95, 0.95, 0.94),) + FABRICS[1:4]) if sum(colour[:3]) < 2.4 else shade(colour, 0.6)
        parts.append(block((x0 - 0.0005, y - 0.012, top - t + 0.0005), (x1 + 0.0005, y, top + 0.0005), stripe,
                           "fabric", collision="none"))
    # Terry cloth folded loosely, with air between the loops.
    return small_object("towel", parts, ["towel"], 130.0, BATHROOM + ["bedroom"])


def make_toilet_paper(rng: np.random.Generator) -> AssetModel:
    outer, inner, h = rng.uniform(0.048, 0.06), rng.uniform(0.019, 0.022), rng.uniform(0.095, 0.11)
    paper = pick(rng, ((0.96, 0.96, 0.95), (0.95, 0.93, 0.87), (0.95, 0.9, 0.91), (0.9, 0.93, 0.96)), jitter=0.02)
    card = pick(rng, ((0.62, 0.5, 0.36), (0.7, 0.6, 0.45), (0.55, 0.45, 0.35)), jitter=0.05)
    parts = [annulus((outer, outer), (inner, inner), 0.0, h, paper, "paper", segments=10),
             # The cardboard core lines the hole, just inside the paper's inner face.
             annulus((inner + 0.001, inner + 0.001), (inner - 0.0015, inner - 0.0015), 0.0003, h - 0.0003, card, "paper",
                      collision="none")]
    return small_object("toilet_paper", parts, ["toilet paper", "toilet roll", "tissue roll"], 200.0, BATHROOM)


FACTORIES = {
    "pen": make_pen,
    "notebook": make_notebook,
    "stapler": make_stapler,
    "scissors": make_scissors,
    "keyboard": make_keyboard,
    "computer_mouse": make_computer_mouse,
    "tablet": make_tablet,
    "soap": make_soap,
    "shampoo": make_shampoo,
    "towel": make_towel,
    "toilet_paper": make_toilet_paper,
}

register_builtins(FACTORIES)
