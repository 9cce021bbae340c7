"""Built-in small objects of living rooms and bedrooms: decor, textiles and things people keep about (pickupable, parametric, seeded, low-poly; registered on import).

The conventions are those of :mod:`legent_gym.world.assets.library.objects`.
"""

from __future__ import annotations

import numpy as np

from legent_gym.world.assets.library.common import (
    BEDDING,
    BRIGHT_PLASTICS,
    CERAMICS,
    DARK_PLASTICS,
    FABRICS,
    FOLIAGE,
    GLASSES,
    METALS,
    RGBA,
    SCREEN,
    WHITE,
    WICKERS,
    WOODS,
    Colours,
    block,
    lathe,
    pick,
    register_builtins,
    rod,
    shade,
    small_object,
    transformed,
)
from legent_gym.world.assets.model import AssetModel, Collision, Part, cylinder_part, sphere_part

WAXES: Colours = (
    (0.95, 0.93, 0.86),  # ivory
    (0.97, 0.97, 0.95),  # white
    (0.62, 0.12, 0.14),  # burgundy
    (0.88, 0.78, 0.55),  # honey
    (0.70, 0.80, 0.68),  # sage
    (0.85, 0.62, 0.65),  # rose
)
KRAFTS: Colours = (
    (0.72, 0.55, 0.36),
    (0.66, 0.50, 0.32),
    (0.78, 0.62, 0.42),
    (0.60, 0.45, 0.29),
)
#: River pebbles of a stacked-stone cairn.
PEBBLES: Colours = (
    (0.55, 0.55, 0.53),  # grey
    (0.35, 0.35, 0.36),  # slate
    (0.72, 0.68, 0.60),  # sandstone
    (0.88, 0.87, 0.84),  # marble
    (0.45, 0.40, 0.35),  # basalt brown
)
SOIL: RGBA = (0.25, 0.18, 0.12, 1.0)
COSY = ["living_room", "bedroom"]



def _turned(part: Part, angle: float, scale: tuple[float, float, float] = (1.0, 1.0, 1.0),
            offset: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Part:
    """``part`` turned ``angle`` radians about z, then scaled and moved."""
    c, s = np.cos(angle), np.sin(angle)
    mat = np.eye(4)
    mat[:3, :3] = np.diag(scale) @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    mat[:3, 3] = offset
    return part.transformed(mat)


def _sheared(part: Part, slope: float) -> Part:
    """``part`` with every point moved ``slope * z`` along y: a slab leaning on a flat foot."""
    mat = np.eye(4)
    mat[1, 2] = slope
    return part.transformed(mat)


def _ball(center, radius: float, rgba: RGBA, material: str, *, squash: float = 1.0,
          collision: Collision = "hull") -> Part:
    """A 48-triangle ball (octagonal lathe), cheaper than an icosphere for small details."""
    k = np.sqrt(0.5)
    return lathe([(0.0, -radius * squash), (k * radius, -k * radius * squash), (radius, 0.0),
                  (k * radius, k * radius * squash), (0.0, radius * squash)],
                 rgba, material, segments=8, center=center, collision=collision)


def _wick(top: float) -> Part:
    return block((-0.001, -0.001, top - 0.002), (0.001, 0.001, top + 0.01), (0.12, 0.1, 0.08, 1.0),
                 "plain", collision="none")


# ---------------------------------------------------------------------------------------
# Decor.


def make_candle(rng: np.random.Generator) -> AssetModel:
    wax = pick(rng, WAXES, jitter=0.04)
    kind = ("pillar", "jar", "taper")[int(rng.integers(3))]
    rooms = ["living_room", "dining_room", "bedroom", "bathroom"]
    if kind == "pillar":
        r, h = rng.uniform(0.025, 0.045), rng.uniform(0.07, 0.2)
        parts = [rod(0, 0, 0.0, h, r, wax, "plain", segments=10), _wick(h)]
        return small_object("candle", parts, ["candle", "pillar candle"], 900.0, rooms)
    if kind == "jar":
        r, h = rng.uniform(0.035, 0.05), rng.uniform(0.07, 0.12)
        glass = pick(rng, GLASSES)
        fill = h * rng.uniform(0.55, 0.8)
        jar = lathe([(r, 0.0), (r * 1.04, 0.5 * h), (r, h), (r - 0.004, h), (r * 1.04 - 0.004, 0.5 * h),
                     (r - 0.004, 0.006)], glass, "glass", segments=8)
        parts = [jar, rod(0, 0, 0.006, fill, r - 0.003, wax, "plain", collision="none"), _wick(fill)]
        # The jar's shell is glass; the wax inside adds its weight, so the shell counts heavier.
        return small_object("candle", parts, ["candle", "jar candle", "scented candle"], 5000.0, rooms)
    # A taper candle in a candlestick: foot, stem and a drip cup on top.
    metal = rng.random() < 0.7
    holder = pick(rng, METALS[:2] + METALS[4:] if metal else CERAMICS[:2] + CERAMICS[5:6], jitter=0.03)
    foot, stand_h = rng.uniform(0.04, 0.055), rng.uniform(0.06, 0.14)
    stem, cup = rng.uniform(0.008, 0.012), rng.uniform(0.016, 0.02)
    body = lathe([(foot, 0.0), (foot, 0.008), (stem, 0.025), (stem, stand_h - 0.015), (cup, stand_h)],
                 holder, "metal" if metal else "ceramic", segments=8)
    taper_h = rng.uniform(0.12, 0.2)
    parts = [body, rod(0, 0, stand_h - 0.01, stand_h + taper_h, 0.011, wax, "plain", radius_top=0.009),
             _wick(stand_h + taper_h)]
    return small_object("candle", parts, ["candle", "candlestick", "taper candle"], [2500.0, 900.0, 900.0], rooms)


#: Photo palettes: (sky, ground) pairs for a landscape print.
PHOTO_SKIES: Colours = ((0.45, 0.65, 0.88), (0.75, 0.78, 0.82), (0.95, 0.62, 0.35), (0.25, 0.3, 0.5))
PHOTO_GROUNDS: Colours = ((0.3, 0.5, 0.25), (0.82, 0.75, 0.55), (0.2, 0.3, 0.45), (0.35, 0.3, 0.28))


def make_picture_frame(rng: np.random.Generator) -> AssetModel:
    long_side = rng.uniform(0.15, 0.28)
    short_side = long_side * rng.uniform(0.7, 0.82)
    w, h = (long_side, short_side) if rng.random() < 0.5 else (short_side, long_side)
    border, t = rng.uniform(0.01, 0.025), rng.uniform(0.01, 0.02)
    frame = pick(rng, WOODS + METALS[1:4] + ((0.08, 0.08, 0.08),), jitter=0.04)
    mat_c = pick(rng, ((0.96, 0.95, 0.92), (0.9, 0.88, 0.82), (0.12, 0.12, 0.12)), jitter=0.02)
    sky, ground = pick(rng, PHOTO_SKIES, jitter=0.1), pick(rng, PHOTO_GROUNDS, jitter=0.1)
    slope = -np.tan(rng.uniform(np.radians(10), np.radians(16)))  # leaning back, away from +y
    hw, m = w / 2, border * rng.uniform(0.3, 0.6)  # m: the mat showing inside the frame
    horizon = rng.uniform(0.35, 0.6) * (h - 2 * border - 2 * m) + border + m
    # The frame is sheared rather than tilted, so it stands on a flat foot along its bottom edge.
    slab = [block((-hw, -t, 0.0), (hw, 0.0, h), frame, "wood", collision="hull"),
            block((-hw + border, 0.0, border), (hw - border, 0.0008, h - border), mat_c, "paper",
                  collision="none"),
            block((-hw + border + m, 0.0, border + m), (hw - border - m, 0.0015, horizon), ground, "paper",
                  collision="none"),
            block((-hw + border + m, 0.0, horizon), (hw - border - m, 0.0015, h - border - m), sky, "paper",
                  collision="none")]
    parts = [_sheared(p, float(slope)) for p in slab]
    # The back strut meets the frame's back at strut_h and stands on the table behind it.
    strut_h, reach = h * rng.uniform(0.55, 0.7), h * rng.uniform(0.3, 0.4)
    sw, st = min(0.03, 0.3 * w), 0.005
    top_y = -t + slope * strut_h
    strut = block((-sw / 2, -reach - st, 0.0), (sw / 2, -reach, strut_h), shade(frame, 0.8), "wood",
                  collision="hull")
    parts.append(_sheared(strut, float((top_y + reach) / strut_h)))
    return small_object("picture_frame", parts, ["picture frame", "photo frame", "photo", "frame"], 700.0,
                  ["living_room", "bedroom", "office", "hallway"])


def _clock_face(centre_y: float, centre_z: float, radius: float, face: RGBA, hands: RGBA,
                rng: np.random.Generator) -> list[Part]:
    """A dial facing +y with hour and minute hands at a random time."""
    disc = cylinder_part((0.0, 0.0, 0.0), radius, 0.003, face, segments=10, collision="none", material="plastic")
    parts = [transformed(disc, rotate_x=np.pi / 2, offset=(0.0, centre_y, centre_z))]
    y = centre_y + 0.0015
    for length, width in ((0.55 * radius, 0.006), (0.85 * radius, 0.004)):
        hand = block((-width / 2, y, centre_z - 0.1 * radius), (width / 2, y + 0.001, centre_z + length), hands,
                     "metal", collision="none")
        parts.append(transformed(hand, rotate_y=float(rng.uniform(0, 2 * np.pi)), pivot=(0.0, y, centre_z)))
    return parts


def make_alarm_clock(rng: np.random.Generator) -> AssetModel:
    material = "metal" if rng.random() < 0.2 else "plastic"
    body = pick(rng, METALS[1:2] + METALS[4:] if material == "metal" else BRIGHT_PLASTICS + DARK_PLASTICS,
                jitter=0.04)
    rooms = ["bedroom", "office"]
    if rng.random() < 0.5:  # a round analogue clock on two feet
        r, depth = rng.uniform(0.04, 0.058), rng.uniform(0.03, 0.05)
        foot_h = rng.uniform(0.006, 0.012)
        # Ten segments about y put a flat face at the bottom (between 252 and 288 degrees).
        cz = foot_h + r * np.cos(np.radians(18))
        drum = cylinder_part((0.0, 0.0, 0.0), r, depth, body, segments=10, material=material)
        parts = [transformed(drum, rotate_x=np.pi / 2, offset=(0.0, 0.0, cz))]
        for sx in (-1, 1):
            parts.append(block((sx * 0.7 * r - 0.007, -0.35 * depth, 0.0), (sx * 0.7 * r + 0.007, 0.35 * depth,
                               foot_h + 0.35 * r), shade(body, 0.7), material))
        parts.append(block((-0.008, -0.006, cz + 0.9 * r), (0.008, 0.006, cz + r + 0.008), shade(body, 0.8),
                           material))
        face = pick(rng, ((0.96, 0.95, 0.92), (0.92, 0.88, 0.78), (0.1, 0.1, 0.1)), jitter=0.02)
        parts += _clock_face(depth / 2 + 0.0015, float(cz), 0.85 * r, face, shade(body, 0.4) if face[0] > 0.5
                             else (0.9, 0.9, 0.9, 1.0), rng)
        return small_object("alarm_clock", parts, ["alarm clock", "clock"], 600.0, rooms)
    # A digital clock: a box with a display on its front.
    w, d, h = rng.uniform(0.09, 0.15), rng.uniform(0.045, 0.075), rng.uniform(0.05, 0.09)
    digits = pick(rng, ((0.95, 0.2, 0.15), (0.3, 0.95, 0.4), (0.35, 0.75, 0.98), (0.98, 0.98, 0.95)), jitter=0.02)
    hw, hd = w / 2, d / 2
    parts = [block((-hw, -hd, 0.0), (hw, hd, h), body, material),
             block((-hw + 0.008, hd, 0.2 * h), (hw - 0.008, hd + 0.001, 0.8 * h), SCREEN, "glass",
                   collision="none"),
             block((-hw + 0.018, hd + 0.001, 0.38 * h), (hw - 0.018, hd + 0.0015, 0.62 * h), digits, "plastic",
                   collision="none"),
             block((-0.3 * hw, -0.4 * hd, h), (0.3 * hw, 0.2 * hd, h + 0.005), shade(body, 0.75), "plastic")]
    return small_object("alarm_clock", parts, ["alarm clock", "clock", "digital clock"], 500.0, rooms)


LAMP_SHADES: Colours = ((0.96, 0.94, 0.87), (0.9, 0.85, 0.72), (0.85, 0.85, 0.85), (0.35, 0.35, 0.37),
                        (0.2, 0.35, 0.3), (0.75, 0.55, 0.4))


def _lampshade(z0: float, height: float, r_bottom: float, r_top: float, rgba: RGBA) -> Part:
    """A shade open underneath: in up the inside to a closed top, out and back up the outside."""
    wall = 0.003
    return lathe([(r_top - wall, z0 + height - wall), (r_bottom - wall, z0), (r_bottom, z0), (r_top, z0 + height)],
                 rgba, "fabric", segments=8)


def make_desk_lamp(rng: np.random.Generator) -> AssetModel:
    shade_c = pick(rng, LAMP_SHADES, jitter=0.04)
    shade_h, r_bottom = rng.uniform(0.1, 0.17), rng.uniform(0.08, 0.13)
    r_top = r_bottom * (rng.uniform(0.85, 1.0) if rng.random() < 0.4 else rng.uniform(0.5, 0.7))
    if rng.random() < 0.5:  # a weighted metal disc and a thin stem
        metal = pick(rng, METALS, jitter=0.03)
        base_r, base_h = rng.uniform(0.055, 0.08), rng.uniform(0.018, 0.03)
        stem_top = base_h + rng.uniform(0.12, 0.22)
        parts = [rod(0, 0, 0.0, base_h, base_r, metal, "metal", segments=10),
                 rod(0, 0, base_h, stem_top + 0.6 * shade_h, 0.007, metal, "metal", segments=6),
                 block((base_r * 0.5, -0.006, base_h), (base_r * 0.5 + 0.012, 0.006, base_h + 0.008),
                       shade(metal, 0.6), "plastic")]
        densities = [4000.0, 4000.0, 1000.0]
    else:  # a ceramic urn with a short neck
        ceramic = pick(rng, CERAMICS, jitter=0.04)
        r, body_h = rng.uniform(0.05, 0.075), rng.uniform(0.12, 0.22)
        stem_top = body_h + rng.uniform(0.03, 0.06)
        parts = [lathe([(0.75 * r, 0.0), (r, 0.4 * body_h), (0.8 * r, 0.8 * body_h), (0.3 * r, body_h)],
                       ceramic, "ceramic", segments=8),
                 rod(0, 0, body_h - 0.005, stem_top + 0.6 * shade_h, 0.008, METALS[4] + (1.0,), "metal",
                     segments=6)]
        # The urn is hollow: count it as a ceramic shell with a weighted foot.
        densities = [900.0, 4000.0]
    parts.append(_lampshade(stem_top, shade_h, r_bottom, r_top, shade_c))
    densities.append(700.0)
    return small_object("desk_lamp", parts, ["lamp", "desk lamp", "table lamp"], densities,
                  ["office", "bedroom", "living_room"])


def make_pillow(rng: np.random.Generator) -> AssetModel:
    fabric = pick(rng, FABRICS + BEDDING, jitter=0.05)
    if rng.random() < 0.7:
        w = rng.uniform(0.35, 0.52)
        d = w * rng.uniform(0.95, 1.0)
    else:  # a lumbar cushion
        w, d = rng.uniform(0.42, 0.55), rng.uniform(0.28, 0.35)
    t = rng.uniform(0.09, 0.17)
    # Four segments make a square in cross-section; the widest ring is the seam, the top a soft dome.
    body = lathe([(0.8, 0.0), (0.96, 0.25 * t), (1.0, 0.5 * t), (0.92, 0.78 * t), (0.6, 0.95 * t), (0.0, t)],
                 fabric, "fabric", segments=4)
    s = np.sqrt(0.5)
    parts = [_turned(body, np.pi / 4, (w * s, d * s, 1.0))]
    if rng.random() < 0.4:  # a button tufting the middle
        parts.append(rod(0, 0, t - 0.01, t + 0.004, 0.012, shade(fabric, 0.7), "fabric", segments=6,
                         collision="none"))
    # Polyester fill: a cushion of 45 cm weighs about half a kilogram.
    return small_object("pillow", parts, ["pillow", "cushion", "throw pillow"], 25.0, COSY)


def make_basket(rng: np.random.Generator) -> AssetModel:
    wicker = pick(rng, WICKERS, jitter=0.05)
    rb, h = rng.uniform(0.09, 0.15), rng.uniform(0.1, 0.22)
    rt, wall = rb * rng.uniform(1.05, 1.25), 0.007
    shape = ("round", "oval", "square")[int(rng.integers(3))]
    profile = [(rb, 0.0), (0.5 * (rb + rt), 0.5 * h), (rt, h), (rt - wall, h), (0.5 * (rb + rt) - wall, 0.5 * h),
               (rb - wall, 0.01)]
    if shape == "square":
        s = np.sqrt(0.5)
        scale = (1.0, rng.uniform(0.65, 1.0), 1.0)
        parts = [_turned(lathe(profile, wicker, "wood", segments=4), np.pi / 4, (scale[0] / s, scale[1] / s, 1.0))]
        reach, across = rt * scale[0], rt * scale[1]
    else:
        sy = 1.0 if shape == "round" else rng.uniform(0.65, 0.8)
        parts = [lathe(profile, wicker, "wood", segments=8, scale_xy=(1.0, sy))]
        reach, across = rt, rt * sy
    names = ["basket", "wicker basket"]
    if rng.random() < 0.5:  # a carrying handle arching over the top along x
        grip = shade(wicker, 0.85)
        top = h + rng.uniform(0.08, 0.14)
        bw, bt = min(0.02, 0.3 * across), 0.01
        for sx in (-1, 1):
            x = sx * (reach - wall - bt / 2)
            parts.append(block((x - bt / 2, -bw / 2, 0.5 * h), (x + bt / 2, bw / 2, top), grip, "wood"))
        parts.append(block((-reach + wall, -bw / 2, top - bt), (reach - wall, bw / 2, top), grip, "wood"))
    # Woven cane is mostly air: about 400 kg/m^3 counted over the wall.
    return small_object("basket", parts, names, 400.0, ["living_room", "bedroom", "bathroom", "hallway"])


def make_cardboard_box(rng: np.random.Generator) -> AssetModel:
    w, h = rng.uniform(0.18, 0.45), rng.uniform(0.1, 0.3)
    d = w * rng.uniform(0.55, 0.9)
    card = pick(rng, KRAFTS + ((0.9, 0.9, 0.88),), jitter=0.04)
    tape = pick(rng, ((0.8, 0.66, 0.42), (0.55, 0.4, 0.25), (0.92, 0.92, 0.9), (0.75, 0.72, 0.62)), jitter=0.03)
    hw, hd, tw = w / 2, d / 2, rng.uniform(0.045, 0.055) / 2
    flap = min(0.06, 0.4 * h)
    parts = [block((-hw, -hd, 0.0), (hw, hd, h), card, "paper"),
             # Tape along the seam of the top flaps, folded down over both ends.
             block((-hw - 0.0005, -tw, h - flap), (hw + 0.0005, tw, h + 0.0005), tape, "plastic", collision="none")]
    if rng.random() < 0.6:  # a shipping label on the top
        lw, ld = min(0.1, 0.4 * w), min(0.07, 0.6 * hd)
        x0 = rng.uniform(-hw + 0.01, hw - 0.01 - lw)
        parts.append(block((x0, tw + 0.005, h), (x0 + lw, min(tw + 0.005 + ld, hd - 0.005), h + 0.0008), WHITE,
                           "paper", collision="none"))
    # An average of packed and empty boxes: corrugated board plus some contents.
    return small_object("cardboard_box", parts, ["box", "cardboard box", "package", "parcel"],
                  float(rng.uniform(25.0, 60.0)), ["hallway", "office", "living_room", "bedroom"])


def make_potted_plant(rng: np.random.Generator) -> AssetModel:
    pot_c = pick(rng, CERAMICS + ((0.72, 0.42, 0.3), (0.85, 0.85, 0.85)), jitter=0.05)
    leaves = pick(rng, FOLIAGE, jitter=0.12)
    r, h = rng.uniform(0.045, 0.075), rng.uniform(0.07, 0.12)
    rim = 0.9 * r
    # Solid below the soil line: the pot and its soil weigh as one.
    parts = [lathe([(0.75 * r, 0.0), (r, h), (rim, h), (rim, h - 0.012)], pot_c, "ceramic", segments=8)]
    densities = [1100.0]
    soil = rod(0, 0, h - 0.014, h - 0.01, rim - 0.001, SOIL, "plain", collision="none")
    kind = ("bush", "topiary", "cactus", "spiky")[int(rng.integers(4))]
    names = ["potted plant", "small plant", "houseplant"]
    if kind == "bush":
        cr = r * rng.uniform(1.1, 1.5)
        squash = rng.uniform(0.8, 1.1)
        parts.append(sphere_part((0, 0, h - 0.01 + 0.8 * cr * squash), cr, leaves, scale=(1.0, 1.0, squash),
                                 material="plain"))
        densities.append(150.0)
    elif kind == "topiary":
        trunk = rng.uniform(0.03, 0.06)
        cone_r, cone_h = r * rng.uniform(0.9, 1.3), rng.uniform(0.12, 0.22)
        parts += [soil, rod(0, 0, h - 0.012, h + trunk + 0.01, 0.005, (0.4, 0.3, 0.2, 1.0), "wood", segments=6),
                  lathe([(cone_r, 0.0), (0.0, cone_h)], leaves, "plain", segments=8, center=(0, 0, h + trunk))]
        densities += [0.0, 700.0, 250.0]
    elif kind == "cactus":
        cr, ch = rim * rng.uniform(0.45, 0.65), rng.uniform(0.08, 0.2)
        green = pick(rng, ((0.3, 0.5, 0.3), (0.4, 0.55, 0.35), (0.25, 0.42, 0.32)), jitter=0.08)
        parts += [soil, lathe([(cr, 0.0), (cr, ch), (0.6 * cr, ch + 0.3 * cr), (0.0, ch + 0.45 * cr)], green,
                              "plain", segments=8, center=(0, 0, h - 0.012))]
        densities += [0.0, 900.0]
        names.append("cactus")
    else:  # a snake plant: stiff blades fanning out of the soil
        parts.append(soil)
        densities.append(0.0)
        for k in range(6):
            blade_h = rng.uniform(0.1, 0.22)
            blade = lathe([(1.0, 0.0), (0.0, blade_h)], shade(leaves, rng.uniform(0.8, 1.2)), "plain",
                          segments=3, scale_xy=(0.014, 0.004), collision="none")
            tilt, azimuth = rng.uniform(0.05, 0.3), 2 * np.pi * k / 6 + rng.uniform(-0.4, 0.4)
            blade = transformed(blade, rotate_x=float(tilt))
            parts.append(_turned(blade, float(azimuth), offset=(0.3 * rim * np.cos(azimuth),
                                                                0.3 * rim * np.sin(azimuth), h - 0.012)))
            densities.append(0.0)
    return small_object("potted_plant", parts, names, densities,
                  ["living_room", "office", "kitchen", "bedroom", "dining_room", "bathroom"])


#: Figurine finishes: (palette, material, density of the (partly hollow) cast, kg/m^3).
FINISHES: dict[str, tuple[Colours, str, float]] = {
    "porcelain": (CERAMICS, "ceramic", 1500.0),
    "bronze": (((0.55, 0.38, 0.2), (0.78, 0.64, 0.35), (0.3, 0.25, 0.2)), "metal", 3500.0),
    "wood": (WOODS[:6], "wood", 700.0),
}


def make_figurine(rng: np.random.Generator) -> AssetModel:
    kind = ("statuette", "cat", "stones")[int(rng.integers(3))]
    rooms = ["living_room", "bedroom", "office", "hallway"]
    names = ["figurine", "statue", "ornament"]
    if kind == "stones":  # a cairn of flattened pebbles
        parts, z = [], 0.0
        r = rng.uniform(0.04, 0.06)
        for _ in range(3):
            t = r * rng.uniform(0.55, 0.8)
            parts.append(lathe([(0.6 * r, 0.0), (r, 0.4 * t), (0.7 * r, 0.85 * t), (0.0, t)],
                               pick(rng, PEBBLES, jitter=0.06), "plain", segments=8, center=(0, 0, z)))
            z += 0.9 * t
            r *= rng.uniform(0.7, 0.85)
        return small_object("figurine", parts, names + ["stones"], 2600.0, rooms)
    palette, material, density = FINISHES[list(FINISHES)[int(rng.integers(len(FINISHES)))]]
    colour = pick(rng, palette, jitter=0.05)
    if kind == "statuette":  # a robed figure on a square plinth
        rb, body_h = rng.uniform(0.018, 0.03), rng.uniform(0.07, 0.16)
        plinth = rng.uniform(2.4, 3.0) * rb
        ph = rng.uniform(0.012, 0.025)
        head = rng.uniform(0.5, 0.6) * rb
        parts = [block((-plinth / 2, -plinth / 2, 0.0), (plinth / 2, plinth / 2, ph), shade(colour, 0.75),
                       material),
                 lathe([(rb, ph), (0.8 * rb, ph + 0.5 * body_h), (0.6 * rb, ph + 0.85 * body_h),
                        (0.35 * rb, ph + body_h)], colour, material, segments=8),
                 _ball((0, 0, ph + body_h + 0.8 * head), head, colour, material, squash=1.15)]
        return small_object("figurine", parts, names + ["statuette"], density, rooms)
    # A sitting cat.
    r = rng.uniform(0.022, 0.035)
    body_h = r * rng.uniform(2.2, 3.0)
    head = 0.75 * r
    hz = body_h + 0.6 * head
    parts = [lathe([(r, 0.0), (1.05 * r, 0.3 * body_h), (0.75 * r, 0.7 * body_h), (0.5 * r, body_h)], colour,
                   material, segments=8, scale_xy=(1.0, 0.85)),
             _ball((0, 0, hz), head, colour, material, squash=0.9)]
    for sx in (-1, 1):
        parts.append(lathe([(1.0, 0.0), (0.0, 0.7 * head)], colour, material, segments=3,
                           scale_xy=(0.35 * head, 0.2 * head), center=(sx * 0.5 * head, 0.0, hz + 0.6 * head)))
    # The tail lies along the ground beside the body.
    parts.append(block((0.3 * r, -0.4 * r, 0.0), (1.25 * r, 0.6 * r, 0.25 * r), shade(colour, 0.9), material))
    return small_object("figurine", parts, names + ["cat figurine"], density, rooms)


def make_game_controller(rng: np.random.Generator) -> AssetModel:
    shell = pick(rng, DARK_PLASTICS + BRIGHT_PLASTICS[:2], jitter=0.04)
    trim = (0.85, 0.85, 0.86, 1.0) if shell[0] < 0.5 else (0.12, 0.12, 0.13, 1.0)
    rooms = ["living_room", "bedroom"]
    if rng.random() < 0.6:  # a modern gamepad: two grips, two sticks
        w, d, t = rng.uniform(0.1, 0.12), rng.uniform(0.05, 0.06), rng.uniform(0.022, 0.03)
        hw, hd = w / 2, d / 2
        parts = [block((-hw, -hd, 0.0), (hw, hd, t), shell, "plastic")]
        gl, gw = rng.uniform(0.045, 0.06), 0.03
        for sx in (-1, 1):
            grip = block((-gw / 2, -gl, 0.0), (gw / 2, 0.0, 0.9 * t), shell, "plastic", collision="hull")
            parts.append(_turned(grip, float(sx * 0.35), offset=(sx * (hw - gw / 2), 0.0, 0.0)))
        pad = (-0.55 * hw, 0.25 * hd)
        for a, b in ((0.012, 0.004), (0.004, 0.012)):
            parts.append(block((pad[0] - a, pad[1] - b, t), (pad[0] + a, pad[1] + b, t + 0.002), trim, "plastic",
                               collision="none"))
        for x, y in ((-0.3 * hw, -0.45 * hd), (0.3 * hw, -0.45 * hd)):
            parts.append(rod(x, y, t - 0.002, t + 0.008, 0.008, trim, "plastic", segments=6, collision="none"))
        buttons = pick(rng, BRIGHT_PLASTICS, jitter=0.0)
        bx, by = 0.55 * hw, 0.25 * hd
        for dx, dy in ((0.01, 0.0), (-0.01, 0.0), (0.0, 0.01), (0.0, -0.01)):
            parts.append(block((bx + dx - 0.0035, by + dy - 0.0035, t), (bx + dx + 0.0035, by + dy + 0.0035, t + 0.003),
                               buttons, "plastic", collision="none"))
        return small_object("game_controller", parts, ["game controller", "controller", "gamepad"], 800.0, rooms)
    # A flat retro pad.
    w, d, t = rng.uniform(0.11, 0.14), rng.uniform(0.048, 0.058), rng.uniform(0.014, 0.02)
    hw, hd = w / 2, d / 2
    face = pick(rng, ((0.12, 0.12, 0.12), (0.55, 0.56, 0.58), (0.9, 0.9, 0.88)), jitter=0.03)
    parts = [block((-hw, -hd, 0.0), (hw, hd, t), shell, "plastic"),
             block((-hw + 0.006, -hd + 0.006, t), (hw - 0.006, hd - 0.006, t + 0.0008), face, "plastic",
                   collision="none")]
    px = -0.6 * hw
    for a, b in ((0.011, 0.0035), (0.0035, 0.011)):
        parts.append(block((px - a, -b, t), (px + a, b, t + 0.003), (0.08, 0.08, 0.08, 1.0), "plastic",
                           collision="none"))
    red = pick(rng, BRIGHT_PLASTICS[:2] + ((0.1, 0.1, 0.1),), jitter=0.03)
    for x in (0.45 * hw, 0.75 * hw):
        parts.append(rod(x, -0.1 * hd, t, t + 0.003, 0.0055, red, "plastic", collision="none"))
    for x in (-0.12 * hw, 0.12 * hw):
        parts.append(block((x - 0.006, -0.2 * hd, t), (x + 0.006, -0.05 * hd, t + 0.0015), shade(face, 0.5),
                           "plastic", collision="none"))
    return small_object("game_controller", parts, ["game controller", "controller", "gamepad"], 700.0, rooms)


TISSUE_BOXES: Colours = ((0.95, 0.95, 0.93), (0.74, 0.82, 0.9), (0.66, 0.74, 0.64), (0.9, 0.76, 0.76),
                         (0.88, 0.82, 0.68), (0.55, 0.6, 0.75), (0.95, 0.8, 0.4))


def make_tissue_box(rng: np.random.Generator) -> AssetModel:
    colour = pick(rng, TISSUE_BOXES, jitter=0.05)
    if rng.random() < 0.6:  # the long flat kind
        w, d, h = rng.uniform(0.21, 0.26), rng.uniform(0.11, 0.13), rng.uniform(0.06, 0.1)
        slot = (0.38 * w, 0.018)
    else:  # the cube kind
        w = rng.uniform(0.11, 0.13)
        d, h = w, w * rng.uniform(1.0, 1.15)
        slot = (0.28 * w, 0.2 * w)
    hw, hd = w / 2, d / 2
    parts = [block((-hw, -hd, 0.0), (hw, hd, h), colour, "paper"),
             block((-hw - 0.0005, -hd - 0.0005, 0.35 * h), (hw + 0.0005, hd + 0.0005, 0.55 * h),
                   shade(colour, rng.uniform(0.7, 0.85)), "paper", collision="none"),
             block((-slot[0], -slot[1], h), (slot[0], slot[1], h + 0.0008), shade(colour, 0.6), "paper",
                   collision="none"),
             lathe([(1.0, h), (0.0, h + rng.uniform(0.04, 0.07))], WHITE, "paper", segments=4,
                   scale_xy=(0.45 * slot[0], max(0.5 * slot[1], 0.01)), collision="none")]
    # A full box: sheets of tissue are mostly air.
    return small_object("tissue_box", parts, ["tissue box", "tissues", "box of tissues"], 90.0,
                  ["bedroom", "living_room", "bathroom", "office"])


FACTORIES = {
    "candle": make_candle,
    "picture_frame": make_picture_frame,
    "alarm_clock": make_alarm_clock,
    "desk_lamp": make_desk_lamp,
    "pillow": make_pillow,
    "basket": make_basket,
    "cardboard_box": make_cardboard_box,
    "potted_plant": make_potted_plant,
    "figurine": make_figurine,
    "game_controller": make_game_controller,
    "tissue_box": make_tissue_box,
}

register_builtins(FACTORIES)
