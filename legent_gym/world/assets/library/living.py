"""Built-in living room, bedroom, dining room, office and hallway furniture (parametric, seeded, low-poly; registered on import).

Seating: ottoman, bench, stool, office chair. Storage: filing cabinet (slide drawers),
storage cabinet (hinged doors, shelves inside), shoe rack, sideboard (hinged doors, a shelf
inside, on some a row of drawers above them), chest. Hallway and living room: coat rack,
console table, upright piano.

The conventions are those of :mod:`legent_gym.world.assets.library.furniture`: each factory
draws all of its randomness from the generator it is given and returns an
:class:`AssetModel` in the asset frame (z up, footprint centred on the origin, front facing
+y); doors hinge about a vertical front edge and swing toward +y, drawers slide along +y,
closed is joint value 0.
"""

from __future__ import annotations

import math

import numpy as np

from legent_gym.world.assets.library.common import (
    APPLIANCES,
    DARK_PLASTICS,
    FABRICS,
    LEATHERS,
    METALS,
    RGBA,
    WOODS,
    Handle,
    block,
    door_hinges,
    drawer,
    finish,
    hinged_door,
    lathe,
    legs,
    pick,
    register_builtins,
    rod,
    round_top,
    shade,
    top_receptacle,
    transformed,
    upholstery,
    wood_or_metal,
)
from legent_gym.world.assets.model import AssetModel, Part, Receptacle, cylinder_part

#: How often a frame is wood rather than metal, and a cover leather rather than fabric.
P_WOOD, P_LEATHER = 0.65, 0.3
HANDLES = ("bar", "knob", "pull")
#: Lacquered piano finishes besides the wood ones: gloss black and white.
PIANO_FINISHES = ((0.04, 0.04, 0.045), (0.04, 0.04, 0.045), (0.92, 0.91, 0.89))
#: Office furniture enamels: light grey, beige, black, white.
ENAMELS = ((0.72, 0.73, 0.74), (0.80, 0.77, 0.70), (0.14, 0.14, 0.15), (0.93, 0.93, 0.92))
IVORY: RGBA = (0.95, 0.94, 0.90, 1.0)
EBONY: RGBA = (0.03, 0.03, 0.03, 1.0)
CASTER: RGBA = (0.08, 0.08, 0.09, 1.0)


# ---------------------------------------------------------------------------------------
# Part builders: turned and tilted parts, handles.


def _spun(part: Part, angle: float, about=(0.0, 0.0)) -> Part:
    """``part`` turned by ``angle`` (radians) about the vertical line through ``about``."""
    c, s = np.cos(angle), np.sin(angle)
    m = np.eye(4)
    m[:2, :2] = [[c, -s], [s, c]]
    m[0, 3] = about[0] - c * about[0] + s * about[1]
    m[1, 3] = about[1] - s * about[0] - c * about[1]
    return part.transformed(m)


def _strut(p0, p1, radius: float, rgba: RGBA, material: str, *, segments: int = 8) -> Part:
    """A round bar from point ``p0`` to point ``p1`` (splayed legs, hooks, stretchers)."""
    # Scalar arithmetic: a few small numpy calls cost more than the rest of the part.
    dx, dy, dz = (float(b) - float(a) for a, b in zip(p0, p1))
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    ux, uy, uz = dx / length, dy / length, dz / length
    sin_t = math.hypot(ux, uy)  # the z axis turned about k = (-uy, ux, 0) / sin_t lands on u
    if sin_t > 1e-9:
        kx, ky, c = -uy / sin_t, ux / sin_t, uz
        rot = [[c + kx * kx * (1 - c), kx * ky * (1 - c), ky * sin_t],
               [kx * ky * (1 - c), c + ky * ky * (1 - c), -kx * sin_t],
               [-ky * sin_t, kx * sin_t, c]]
    else:
        rot = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] if uz > 0 else \
            [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
    m = np.array([[*rot[0], (float(p0[0]) + float(p1[0])) / 2], [*rot[1], (float(p0[1]) + float(p1[1])) / 2],
                  [*rot[2], (float(p0[2]) + float(p1[2])) / 2], [0.0, 0.0, 0.0, 1.0]])
    bar = cylinder_part((0.0, 0.0, 0.0), radius, length, rgba, segments=segments, collision="hull",
                        material=material)
    return bar.transformed(m)


def _handle(style: str, x: float, y: float, z: float, rgba: RGBA, *, vertical: bool = False) -> Part:
    """A handle on a front face in the plane ``y``, standing out toward +y, centred at (x, z)."""
    if style == "knob":
        return block((x - 0.015, y, z - 0.015), (x + 0.015, y + 0.025, z + 0.015), rgba, "metal")
    if style == "pull":  # a flat cup pull, always across
        return block((x - 0.05, y, z - 0.012), (x + 0.05, y + 0.015, z + 0.012), rgba, "metal")
    hx, hz = (0.008, 0.07) if vertical else (0.07, 0.008)
    return block((x - hx, y, z - hz), (x + hx, y + 0.028, z + hz), rgba, "metal")


def _pull(style: str, rgba: RGBA, *, vertical: bool = False, label: bool = False) -> Handle:
    """A door or drawer handle of ``style`` (see :func:`_handle`); with ``label``, the card
    holder of a filing drawer under it."""
    def make(x: float, y: float, z: float, height: float) -> list[Part]:
        parts = [_handle(style, x, y, z, rgba, vertical=vertical)]
        if label:
            parts.append(block((x - 0.04, y - 0.002, z - 0.065), (x + 0.04, y + 0.004, z - 0.03), shade(rgba, 1.1),
                               "metal", collision="none"))
        return parts
    return make


def _between_legs(name: str, lo, hi, leg: float, clearance: float) -> Receptacle:
    """A low shelf's rectangle between the legs standing in its corners: clear of them along x
    only, since a narrow shelf has little depth to spare."""
    (x0, y0, _), (x1, y1, z1) = lo, hi
    return Receptacle(name, ((x0 + x1) / 2, (y0 + y1) / 2), ((x1 - x0) / 2 - leg - 0.02, (y1 - y0) / 2 - 0.02),
                      float(z1), "base", float(clearance))


# ---------------------------------------------------------------------------------------
# Seating.


def make_ottoman(rng: np.random.Generator) -> AssetModel:
    cover, material = upholstery(rng, P_LEATHER)
    height = rng.uniform(0.36, 0.48)
    leg_c, leg_m = wood_or_metal(rng, P_WOOD)
    leg_h = rng.uniform(0.06, 0.12) if rng.random() < 0.5 else 0.0
    if rng.random() < 0.55:  # a box ottoman, square or a longer footstool bench
        width = rng.uniform(0.42, 0.6) if rng.random() < 0.6 else rng.uniform(0.7, 0.95)
        depth = min(width, rng.uniform(0.42, 0.62))
        hw, hd = width / 2, depth / 2
        pad = rng.uniform(0.05, 0.1)
        body_top = height - pad
        lo, hi = (-hw + 0.01, -hd + 0.01, body_top), (hw - 0.01, hd - 0.01, height)
        parts = [block((-hw, -hd, leg_h), (hw, hd, body_top), cover, material),
                 block(lo, hi, shade(cover, rng.uniform(1.04, 1.12)), material)]
        if leg_h:
            parts += legs(-hw + 0.02, hw - 0.02, -hd + 0.02, hd - 0.02, 0.0, leg_h, rng.uniform(0.035, 0.05),
                          leg_c, leg_m, round_legs=rng.random() < 0.6)
        else:  # a skirt band round the foot
            parts.append(block((-hw - 0.005, -hd - 0.005, 0.0), (hw + 0.005, hd + 0.005, rng.uniform(0.05, 0.09)),
                               shade(cover, 0.85), material))
        recs = [top_receptacle("top", lo, hi)]
    else:  # a round pouf, drum or bulging
        r, seg = rng.uniform(0.2, 0.3), 14
        bulge = rng.uniform(1.0, 1.08)
        top_r = r * rng.uniform(0.88, 0.96)
        parts = [lathe([(r * rng.uniform(0.85, 0.95), leg_h), (r * bulge, leg_h + (height - leg_h) * 0.4),
                        (r * bulge, leg_h + (height - leg_h) * 0.75), (top_r, height)],
                       cover, material, segments=seg)]
        if leg_h:
            n = 3 if rng.random() < 0.5 else 4
            for k in range(n):
                a = 2 * np.pi * k / n + np.pi / 4
                parts.append(_strut((0.65 * r * np.cos(a), 0.65 * r * np.sin(a), leg_h + 0.01),
                                    (0.8 * r * np.cos(a), 0.8 * r * np.sin(a), 0.0), 0.018, leg_c, leg_m,
                                    segments=6))
        recs = [round_top("top", top_r, seg, height)]
    return finish("ottoman", parts, receptacles=recs, names=["ottoman", "pouf", "footstool", "footrest"],
                  rooms=["living_room", "bedroom"], placement="middle", front_clearance=0.3,
                  mass=float(rng.uniform(4, 14)))


def make_bench(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.8, 1.6), rng.uniform(0.3, 0.45), rng.uniform(0.42, 0.5)
    wood = pick(rng, WOODS)
    frame, frame_m = (wood, "wood") if rng.random() < 0.75 else (pick(rng, METALS), "metal")
    hw, hd = width / 2, depth / 2
    seat_style = ("slab", "slats", "cushion")[int(rng.integers(3))]
    seat_t = rng.uniform(0.03, 0.05)
    seat_z = height - (rng.uniform(0.05, 0.09) if seat_style == "cushion" else 0.0)
    under = seat_z - seat_t
    parts: list[Part] = []
    if seat_style == "slats":  # an odd count, so the middle of the seat is on a slat
        n = 3 if depth < 0.38 else 5
        gap = rng.uniform(0.008, 0.015)
        sd = (depth - (n - 1) * gap) / n
        for i in range(n):
            y0 = -hd + i * (sd + gap)
            parts.append(block((-hw, y0, under), (hw, y0 + sd, seat_z), wood, "wood"))
        seat = top_receptacle("seat", (-hw, -hd, 0.0), (hw, hd, seat_z))
    else:
        parts.append(block((-hw, -hd, under), (hw, hd, seat_z), wood, "wood"))
        if seat_style == "cushion":
            cover, cm = upholstery(rng, P_LEATHER)
            lo, hi = (-hw + 0.015, -hd + 0.015, seat_z), (hw - 0.015, hd - 0.015, height)
            parts.append(block(lo, hi, cover, cm))
            seat = top_receptacle("seat", lo, hi)
        else:
            seat = top_receptacle("seat", (-hw, -hd, 0.0), (hw, hd, seat_z))
    support = ("legs", "sides", "trestle")[int(rng.integers(3))]
    leg = rng.uniform(0.04, 0.06)
    inset = rng.uniform(0.02, 0.08)
    shelf_lo = None
    if support == "legs":
        parts += legs(-hw + inset, hw - inset, -hd + 0.01, hd - 0.01, 0.0, under, leg, frame, frame_m,
                      round_legs=rng.random() < 0.4)
        shelf_lo, shelf_hi = (-hw + inset, -hd + 0.01), (hw - inset, hd - 0.01)
        shelf_inset = leg
    elif support == "sides":
        t = rng.uniform(0.025, 0.04)
        for sx in (-1, 1):
            x0, x1 = sorted((sx * (hw - inset), sx * (hw - inset - t)))
            parts.append(block((x0, -hd + 0.01, 0.0), (x1, hd - 0.01, under), frame, frame_m))
        shelf_lo, shelf_hi = (-hw + inset + t, -hd + 0.02), (hw - inset - t, hd - 0.02)
        shelf_inset = 0.01
    else:  # two posts on feet, joined by a stretcher
        for sx in (-1, 1):
            xc = sx * (hw - inset - 0.06)
            parts += [block((xc - leg / 2, -leg, 0.04), (xc + leg / 2, leg, under), frame, frame_m),
                      block((xc - leg / 2, -hd + 0.02, 0.0), (xc + leg / 2, hd - 0.02, 0.04), frame, frame_m)]
        z = rng.uniform(0.12, 0.2)
        parts.append(block((-hw + inset + 0.06, -0.015, z), (hw - inset - 0.06, 0.015, z + 0.04), frame, frame_m))
    recs = [seat]
    if shelf_lo is not None and rng.random() < 0.5:
        z = rng.uniform(0.08, 0.14)
        lo, hi = (shelf_lo[0], shelf_lo[1], z), (shelf_hi[0], shelf_hi[1], z + 0.02)
        parts.append(block(lo, hi, shade(wood, 0.92), "wood"))
        recs.append(_between_legs("shelf", lo, hi, shelf_inset, under - hi[2]))
    return finish("bench", parts, receptacles=recs, names=["bench", "entryway bench", "hall bench"],
                  rooms=["hallway", "bedroom", "dining_room"], placement="wall", front_clearance=0.5,
                  mass=float(rng.uniform(8, 25)))


def make_stool(rng: np.random.Generator) -> AssetModel:
    height = rng.uniform(0.4, 0.5)
    color, material = wood_or_metal(rng, P_WOOD)
    top_c = color if material == "wood" else pick(rng, WOODS + DARK_PLASTICS)
    top_m = "wood" if material == "wood" or rng.random() < 0.5 else "plastic"
    top_t = rng.uniform(0.025, 0.04)
    padded = rng.random() < 0.35
    pad = rng.uniform(0.03, 0.05) if padded else 0.0
    under = height - pad - top_t
    n = 3 if rng.random() < 0.4 else 4
    splay = rng.random() < 0.6
    parts: list[Part] = []
    if rng.random() < 0.6:  # a round seat
        r, seg = rng.uniform(0.15, 0.2), 14
        parts.append(rod(0, 0, under, under + top_t, r, top_c, top_m, segments=seg))
        if padded:
            cover, cm = upholstery(rng, P_LEATHER)
            parts.append(rod(0, 0, under + top_t, height, r - 0.01, cover, cm, segments=seg))
            rec = round_top("top", r - 0.01, seg, height)
        else:
            rec = round_top("top", r, seg, height)
        reach = r
    else:  # a square seat
        s = rng.uniform(0.3, 0.38) / 2
        parts.append(block((-s, -s, under), (s, s, under + top_t), top_c, top_m))
        lo, hi = (-s + 0.01, -s + 0.01, under + top_t), (s - 0.01, s - 0.01, height)
        if padded:
            cover, cm = upholstery(rng, P_LEATHER)
            parts.append(block(lo, hi, cover, cm))
            rec = top_receptacle("top", lo, hi)
        else:
            rec = top_receptacle("top", (-s, -s, 0.0), (s, s, under + top_t))
        reach = s * 1.2
    leg_r = rng.uniform(0.013, 0.022)
    top_at, foot_at = 0.62 * reach, (rng.uniform(0.95, 1.1) if splay else 0.62) * reach
    rung = rng.uniform(0.14, 0.22) if rng.random() < 0.6 else None
    angles = [2 * np.pi * k / n + (np.pi / 4 if n == 4 else np.pi / 2) for k in range(n)]
    feet = []
    for a in angles:
        c, s_ = np.cos(a), np.sin(a)
        feet.append(((top_at * c, top_at * s_, under), (foot_at * c, foot_at * s_, 0.0)))
        parts.append(_strut(*feet[-1], leg_r, color, material, segments=6 if n == 4 else 8))
    if rung is not None:  # a stretcher ring between the legs (a footrest)
        f = rung / under
        pts = [np.asarray(b) + (np.asarray(t) - np.asarray(b)) * f for t, b in feet]
        for i in range(n):
            parts.append(_strut(pts[i], pts[(i + 1) % n], leg_r * 0.6, color, material, segments=6))
    return finish("stool", parts, receptacles=[rec], names=["stool", "low stool"],
                  rooms=["kitchen", "bedroom", "office", "living_room"], placement="middle", front_clearance=0.3,
                  mass=float(rng.uniform(2, 6)))


def make_office_chair(rng: np.random.Generator) -> AssetModel:
    plastic = pick(rng, DARK_PLASTICS)
    base_c = plastic if rng.random() < 0.6 else pick(rng, METALS[:3])
    base_m = "plastic" if base_c is plastic else "metal"
    cover, cover_m = (pick(rng, FABRICS + DARK_PLASTICS[:2]), "fabric") if rng.random() < 0.75 else \
        (pick(rng, LEATHERS), "leather")
    back_c = cover if rng.random() < 0.6 else pick(rng, DARK_PLASTICS + FABRICS)
    spread, wheel_r = rng.uniform(0.28, 0.34), rng.uniform(0.022, 0.03)
    arm_w, arm_t = rng.uniform(0.04, 0.055), rng.uniform(0.025, 0.035)
    arm_z = 2 * wheel_r
    parts: list[Part] = []
    for k in range(5):  # the five-star base, one arm pointing straight ahead
        a = np.pi / 2 + 2 * np.pi * k / 5
        parts.append(_spun(block((0.0, -arm_w / 2, arm_z), (spread, arm_w / 2, arm_z + arm_t), base_c, base_m,
                                 collision="hull"), a))
        wheel = transformed(rod(spread - 0.025, 0.0, wheel_r - 0.018, wheel_r + 0.018, wheel_r, CASTER, "plastic",
                                segments=6), rotate_x=np.pi / 2, pivot=(spread - 0.025, 0.0, wheel_r))
        parts.append(_spun(wheel, a))
    seat_top = rng.uniform(0.45, 0.53)
    seat_t = rng.uniform(0.07, 0.1)
    sw, sd = rng.uniform(0.46, 0.53) / 2, rng.uniform(0.44, 0.52) / 2
    col_top = seat_top - seat_t - 0.04
    parts += [rod(0, 0, arm_z, arm_z + arm_t + 0.015, rng.uniform(0.04, 0.055), base_c, base_m),
              rod(0, 0, arm_z + arm_t + 0.015, col_top, rng.uniform(0.022, 0.03), pick(rng, METALS[:4]), "metal",
                  radius_top=0.02),
              block((-0.1, -0.1, col_top), (0.1, 0.1, seat_top - seat_t), CASTER, "plastic")]
    seat_lo, seat_hi = (-sw, -sd, seat_top - seat_t), (sw, sd, seat_top)
    parts.append(block(seat_lo, seat_hi, cover, cover_m))
    back_h, back_t = rng.uniform(0.42, 0.72), rng.uniform(0.05, 0.08)
    bw = min(sw, rng.uniform(0.2, 0.25))
    tilt = rng.uniform(0.08, 0.22)
    back_z0 = seat_top + rng.uniform(0.04, 0.1)
    yb = -sd - 0.02
    parts.append(transformed(block((-bw, yb - back_t, back_z0), (bw, yb, back_z0 + back_h), back_c, cover_m,
                                   collision="hull"),
                             rotate_x=tilt, pivot=(0.0, yb, back_z0)))
    parts.append(block((-0.03, yb - 0.015, seat_top - seat_t - 0.02), (0.03, yb + 0.01, back_z0 + 0.08),
                       plastic, "plastic"))  # the spine joining seat and back
    parts.append(block((-0.03, yb - 0.015, seat_top - seat_t - 0.04), (0.03, -0.1, seat_top - seat_t),
                       plastic, "plastic"))
    if rng.random() < 0.65:
        arm_top = seat_top + rng.uniform(0.18, 0.25)
        pad_d = rng.uniform(0.22, 0.28) / 2
        for sx in (-1, 1):
            x0, x1 = sorted((sx * (sw + 0.005), sx * (sw + 0.035)))
            xc = (x0 + x1) / 2
            parts += [block((x0, -0.03, seat_top - seat_t), (x1, 0.03, arm_top - 0.025), plastic, "plastic"),
                      block((xc - 0.03, -pad_d - 0.03, arm_top - 0.025), (xc + 0.03, pad_d - 0.03, arm_top),
                            plastic, "plastic")]
    seat = top_receptacle("seat", (-sw, -sd + 0.02, 0.0), seat_hi, inset=0.05)
    return finish("office_chair", parts, receptacles=[seat],
                  names=["office chair", "desk chair", "swivel chair", "computer chair"],
                  rooms=["office", "bedroom"], placement="middle", front_clearance=0.5,
                  mass=float(rng.uniform(10, 19)))


# ---------------------------------------------------------------------------------------
# Storage.


def make_filing_cabinet(rng: np.random.Generator) -> AssetModel:
    n = int(rng.integers(2, 5))
    if n <= 3 and rng.random() < 0.4:  # a lateral cabinet: wide and shallow
        width, depth = rng.uniform(0.75, 0.92), rng.uniform(0.42, 0.5)
    else:
        width, depth = rng.uniform(0.38, 0.5), rng.uniform(0.5, 0.65)
    metal = rng.random() < 0.65
    if metal:
        body, material = pick(rng, ENAMELS, jitter=0.03), "metal"
        front = body
    else:
        body, material = pick(rng, WOODS), "wood"
        front = body if rng.random() < 0.6 else pick(rng, WOODS)
    handle = pick(rng, METALS)
    style = "pull" if metal and rng.random() < 0.6 else HANDLES[int(rng.integers(3))]
    slot_h = rng.uniform(0.27, 0.33)
    base_z = rng.uniform(0.02, 0.08)
    top_t = 0.02 if metal else 0.025
    top_z = base_z + n * slot_h
    height = top_z + top_t
    hw, hd, t = width / 2, depth / 2, 0.018
    top_lo, top_hi = (-hw - (0.0 if metal else 0.01), -hd, top_z), (hw + (0.0 if metal else 0.01), hd, height)
    parts = [
        block(top_lo, top_hi, body, material),
        block((-hw, -hd, 0.0), (-hw + t, hd, top_z), body, material),
        block((hw - t, -hd, 0.0), (hw, hd, top_z), body, material),
        block((-hw + t, -hd, 0.0), (hw - t, -hd + 0.01, top_z), shade(body, 0.85), material),
        block((-hw + t, -hd + 0.01, 0.0), (hw - t, hd - 0.02, base_z), shade(body, 0.7), material),
    ]
    slots = np.linspace(base_z, top_z, n + 1)
    moving, recs = [], [top_receptacle("top", top_lo, top_hi)]
    for i in range(n):
        label = metal and n < 4
        link, rec = drawer(f"drawer_{i}", -hw + t, hw - t, hd, depth - 0.03, slots[i], slots[i + 1],
                           front=front, body=shade(body, 0.9), material=material,
                           handle=_pull(style, handle, label=label), handle_at=0.72 if label else 0.5)
        moving.append(link)
        recs.append(rec)
    return finish("filing_cabinet", parts, moving=moving, receptacles=recs,
                  names=["filing cabinet", "file cabinet", "file drawers"], rooms=["office"],
                  placement="wall", front_clearance=max(0.8, 0.8 * depth + 0.4),
                  mass=float((18 if metal else 14) + 9 * n * rng.uniform(0.8, 1.2)))


def make_storage_cabinet(rng: np.random.Generator) -> AssetModel:
    doors = 1 if rng.random() < 0.35 else 2
    width = rng.uniform(0.4, 0.6) if doors == 1 else rng.uniform(0.7, 1.0)
    depth, height = rng.uniform(0.35, 0.5), rng.uniform(0.8, 1.9)
    wood, handle = pick(rng, WOODS), pick(rng, METALS)
    front = wood if rng.random() < 0.6 else pick(rng, WOODS + APPLIANCES[:1])
    style = HANDLES[int(rng.integers(3))]
    glass = pick(rng, ((0.78, 0.86, 0.86), (0.7, 0.72, 0.72))) if rng.random() < 0.3 else None
    t, door_t = 0.018, 0.02
    hw, hd = width / 2, depth / 2
    yf = hd - door_t
    inner = shade(wood, 0.9)
    on_legs = rng.random() < 0.4
    foot = rng.uniform(0.1, 0.18) if on_legs else rng.uniform(0.05, 0.09)
    top_t = rng.uniform(0.018, 0.03)
    over = rng.uniform(0.0, 0.02)
    top_lo, top_hi = (-hw - over, -hd, height - top_t), (hw + over, hd + over, height)
    floor_lo, floor_hi = (-hw + t, -hd + 0.01, foot), (hw - t, yf, foot + t)
    parts = [
        block(top_lo, top_hi, wood, "wood"),
        block((-hw, -hd, foot), (-hw + t, yf, height - top_t), wood, "wood"),
        block((hw - t, -hd, foot), (hw, yf, height - top_t), wood, "wood"),
        block((-hw + t, -hd, foot), (hw - t, -hd + 0.01, height - top_t), inner, "wood"),
        block(floor_lo, floor_hi, inner, "wood"),
    ]
    if on_legs:
        leg_c, leg_m = (shade(wood, 0.8), "wood") if rng.random() < 0.6 else (pick(rng, METALS), "metal")
        parts += legs(-hw + 0.02, hw - 0.02, -hd + 0.02, yf - 0.02, 0.0, foot, rng.uniform(0.03, 0.05),
                      leg_c, leg_m, round_legs=rng.random() < 0.5)
    else:
        parts.append(block((-hw + t, -hd + 0.02, 0.0), (hw - t, yf - 0.03, foot), shade(wood, 0.7), "wood"))
    ceiling = height - top_t
    shelves = int(np.clip(round((ceiling - foot - t) / 0.36), 2, 5))  # levels incl. the floor board
    zs = np.linspace(foot, ceiling, shelves + 1)[:-1]
    boards = [(floor_lo, floor_hi)]
    for z in zs[1:]:
        lo, hi = (-hw + t, -hd + 0.01, z), (hw - t, yf - 0.015, z + t)
        parts.append(block(lo, hi, inner, "wood"))
        boards.append((lo, hi))
    recs = []
    for i, (lo, hi) in enumerate(boards):
        above = boards[i + 1][0][2] if i + 1 < len(boards) else ceiling
        recs.append(top_receptacle(f"shelf_{i}", lo, hi, clearance=float(above - hi[2])))
    if height < 1.5:
        recs.append(top_receptacle("top", top_lo, top_hi))
    edges = np.linspace(-hw, hw, doors + 1)
    hinge_left = rng.random() < 0.5
    handle_z = min((foot + height) / 2, 1.05) if height > 1.3 else height - 0.12
    moving = [hinged_door(f"door_{i}", edges[i] + 0.002, edges[i + 1] - 0.002, yf, foot + 0.003,
                          height - top_t - 0.003, hinge_left=(i == 0) if doors == 2 else hinge_left, rgba=front,
                          material="wood", handle=_pull(style, handle, vertical=True), thickness=door_t,
                          handle_z=handle_z, glass=glass)
              for i in range(doors)]
    door_w = float(edges[1] - edges[0])
    return finish("storage_cabinet", parts, moving=moving, receptacles=recs,
                  names=["storage cabinet", "cupboard", "storage cupboard"],
                  rooms=["living_room", "bedroom", "office", "hallway", "dining_room"], placement="wall",
                  front_clearance=max(0.7, door_w + 0.1), mass=float(width * height * rng.uniform(30, 45)))


def make_shoe_rack(rng: np.random.Generator) -> AssetModel:
    width, depth = rng.uniform(0.6, 1.0), rng.uniform(0.26, 0.36)
    n = int(rng.integers(2, 5))
    gap = rng.uniform(0.16, 0.24)
    lift = rng.uniform(0.04, 0.1)
    color, material = wood_or_metal(rng, P_WOOD)
    slats = rng.random() < 0.55
    board_t = rng.uniform(0.015, 0.025)
    hw, hd = width / 2, depth / 2
    zs = [lift + i * gap for i in range(n)]
    height = zs[-1] + board_t
    parts: list[Part] = []
    if material == "metal" or rng.random() < 0.3:  # a frame of four posts with side rails
        post = rng.uniform(0.018, 0.03)
        xi = hw - post
        parts += legs(-hw, hw, -hd, hd, 0.0, height, post, color, material, round_legs=material == "metal")
        for z in zs:
            for sx in (-1, 1):
                x0, x1 = sorted((sx * xi, sx * (xi - 0.015)))
                parts.append(block((x0, -hd + post, z - 0.02), (x1, hd - post, z), color, material))
    else:  # two side panels
        side_t = rng.uniform(0.015, 0.025)
        top_extra = rng.uniform(0.0, 0.06) if rng.random() < 0.3 else 0.0
        for sx in (-1, 1):
            x0, x1 = sorted((sx * hw, sx * (hw - side_t)))
            parts.append(block((x0, -hd, 0.0), (x1, hd, height + top_extra), color, material))
        xi = hw - side_t
        if top_extra:
            height += top_extra
    shelf_c = color if rng.random() < 0.7 else pick(rng, WOODS)
    shelf_m = "wood" if shelf_c is not color else material
    recs = []
    for i, z in enumerate(zs):
        if slats:  # three slats: the rectangle's middle and edges all lie on one
            sgap = rng.uniform(0.015, 0.03)
            sd = (depth - 2 * sgap) / 3
            for k in range(3):
                y0 = -hd + k * (sd + sgap)
                parts.append(block((-xi, y0, z), (xi, y0 + sd, z + board_t), shelf_c, shelf_m))
        else:
            parts.append(block((-xi, -hd, z), (xi, hd, z + board_t), shelf_c, shelf_m))
        above = zs[i + 1] - 0.02 if i + 1 < len(zs) else z + board_t + 1.0
        recs.append(top_receptacle(f"shelf_{i}", (-xi, -hd, z), (xi, hd, z + board_t),
                                   clearance=float(above - z - board_t)))
    return finish("shoe_rack", parts, receptacles=recs, names=["shoe rack", "shoe shelf", "shoe stand"],
                  rooms=["hallway", "bedroom"], placement="wall", front_clearance=0.5,
                  mass=float(rng.uniform(3, 6) + 1.5 * n))


def make_sideboard(rng: np.random.Generator) -> AssetModel:
    """A long low cabinet: two to four hinged doors (the left half hinged on the left, the
    rest on the right) in front of a shelf, and on some a row of two drawers above them."""
    width, depth, height = rng.uniform(1.2, 2.0), rng.uniform(0.4, 0.5), rng.uniform(0.7, 0.9)
    wood, handle = pick(rng, WOODS), pick(rng, METALS)
    front = wood if rng.random() < 0.55 else pick(rng, WOODS + APPLIANCES[:1] + FABRICS[3:5])
    style = HANDLES[int(rng.integers(3))]
    doors = int(np.clip(round(width / rng.uniform(0.45, 0.6)), 2, 4))
    hw, hd, t = width / 2, depth / 2, 0.018
    top_t = rng.uniform(0.02, 0.035)
    yf = hd - 0.02  # the carcass front; the doors and drawers lie in front of it
    leg_style = ("tapered", "square", "plinth")[int(rng.integers(3))]
    foot = rng.uniform(0.12, 0.25) if leg_style != "plinth" else rng.uniform(0.05, 0.09)
    top_lo, top_hi = (-hw - 0.01, -hd, height - top_t), (hw + 0.01, hd + 0.01, height)
    body_top = height - top_t
    inner = shade(wood, 0.9)
    floor_lo, floor_hi = (-hw + t, -hd + 0.01, foot), (hw - t, yf, foot + t)
    parts = [block(top_lo, top_hi, wood, "wood"),
             block((-hw, -hd, foot), (-hw + t, yf, body_top), wood, "wood"),
             block((hw - t, -hd, foot), (hw, yf, body_top), wood, "wood"),
             block((-hw + t, -hd, foot), (hw - t, -hd + 0.01, body_top), inner, "wood"),
             block(floor_lo, floor_hi, inner, "wood")]
    leg_c, leg_m = (shade(wood, 0.85), "wood") if rng.random() < 0.7 else (pick(rng, METALS), "metal")
    if leg_style == "tapered":
        r = rng.uniform(0.02, 0.03)
        for x in (-hw + 0.05, hw - 0.05):
            for y in (-hd + 0.05, yf - 0.05):
                parts.append(rod(x, y, 0.0, foot, r * 0.55, leg_c, leg_m, segments=6, radius_top=r))
    elif leg_style == "square":
        parts += legs(-hw + 0.02, hw - 0.02, -hd + 0.02, yf - 0.02, 0.0, foot, rng.uniform(0.035, 0.05), leg_c,
                      leg_m)
    else:
        parts.append(block((-hw + 0.03, -hd + 0.02, 0.0), (hw - 0.03, yf - 0.03, foot), shade(wood, 0.7), "wood"))
    drawer_row = rng.uniform(0.12, 0.16) if rng.random() < 0.45 else 0.0
    mass = float(width * rng.uniform(25, 40))
    door_top = body_top - drawer_row
    recs = [top_receptacle("top", top_lo, top_hi)]
    if drawer_row or door_top - floor_hi[2] < 0.45:  # one level (the drawers' bottoms above it)
        recs.append(top_receptacle("shelf_0", floor_lo, floor_hi, clearance=door_top - floor_hi[2]))
    else:  # a shelf half way up
        shelf_z = (floor_hi[2] + door_top - t) / 2
        shelf_lo, shelf_hi = (-hw + t, -hd + 0.01, shelf_z), (hw - t, yf - 0.015, shelf_z + t)
        parts.append(block(shelf_lo, shelf_hi, inner, "wood"))
        recs += [top_receptacle("shelf_0", floor_lo, floor_hi, clearance=shelf_z - floor_hi[2]),
                 top_receptacle("shelf_1", shelf_lo, shelf_hi, clearance=door_top - shelf_hi[2])]
    edges = np.linspace(-hw, hw, doors + 1)
    hz = door_top - 0.08 if style == "pull" else (foot + door_top) / 2
    moving = [hinged_door(f"door_{i}", edges[i] + 0.003, edges[i + 1] - 0.003, hd, foot + 0.004, door_top - 0.003,
                          hinge_left=hinge_left, rgba=front, material="wood",
                          handle=_pull(style, handle, vertical=True), handle_z=hz,
                          handle_inset=0.06 if style == "pull" else 0.047, hinge_at_front=True)
              for i, hinge_left in enumerate(door_hinges(doors))]
    if drawer_row:
        for i, (a, b) in enumerate(((-hw, 0.0), (0.0, hw))):
            link, rec = drawer(f"drawer_{i}", a, b, hd, depth - 0.03, door_top, body_top, front=front, body=inner,
                               material="wood", handle=_pull("knob" if style == "knob" else "pull", handle),
                               side_clear=t + 0.008)
            moving.append(link)
            recs.append(rec)
    return finish("sideboard", parts, moving=moving, receptacles=recs,
                  names=["sideboard", "buffet", "credenza"], rooms=["dining_room", "living_room"],
                  placement="wall", front_clearance=0.7, mass=mass)


def make_chest(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.7, 1.2), rng.uniform(0.4, 0.6), rng.uniform(0.42, 0.6)
    wood = pick(rng, WOODS[:6])
    metal = pick(rng, METALS[2:])
    hw, hd = width / 2, depth / 2
    lid_t = rng.uniform(0.03, 0.06)
    over = rng.uniform(0.005, 0.025)
    feet = ("plinth", "bun", "bracket", "none")[int(rng.integers(4))]
    foot = {"plinth": rng.uniform(0.04, 0.07), "bun": rng.uniform(0.05, 0.09), "bracket": rng.uniform(0.06, 0.1),
            "none": 0.0}[feet]
    body_top = height - lid_t
    lid_lo, lid_hi = (-hw - over, -hd - over, body_top), (hw + over, hd + over, height)
    parts = [block((-hw, -hd, foot), (hw, hd, body_top), wood, "wood"),
             block(lid_lo, lid_hi, shade(wood, rng.uniform(0.9, 1.08)), "wood")]
    if feet == "plinth":
        parts.append(block((-hw - 0.012, -hd - 0.012, 0.0), (hw + 0.012, hd + 0.012, foot), shade(wood, 0.8), "wood"))
    elif feet == "bun":
        for x in (-hw + 0.06, hw - 0.06):
            for y in (-hd + 0.06, hd - 0.06):
                parts.append(lathe([(0.03, 0.0), (0.045, foot * 0.5), (0.035, foot)], shade(wood, 0.85), "wood",
                                   segments=6, center=(x, y, 0.0)))
    elif feet == "bracket":
        for sx in (-1, 1):
            x0, x1 = sorted((sx * hw, sx * (hw - 0.1)))
            for y0, y1 in ((-hd, -hd + 0.04), (hd - 0.04, hd)):
                parts.append(block((x0, y0, 0.0), (x1, y1, foot), shade(wood, 0.8), "wood"))
    band = rng.uniform(0.035, 0.06)
    if rng.random() < 0.6:  # iron straps up the front and over the lid, corner caps
        for sx in (-1, 1):
            x = sx * hw * rng.uniform(0.45, 0.6)
            parts += [block((x - band / 2, hd - 0.002, foot), (x + band / 2, hd + 0.004, body_top), metal, "metal",
                            collision="none"),
                      block((x - band / 2, -hd - over, height - 0.002), (x + band / 2, hd + over + 0.004, height + 0.003),
                            metal, "metal", collision="none")]
        for sx in (-1, 1):
            x0, x1 = sorted((sx * (hw + 0.003), sx * (hw - 0.05)))
            parts.append(block((x0, hd - 0.05, foot), (x1, hd + 0.003, foot + 0.05), metal, "metal", collision="none"))
    parts.append(block((-0.035, hd - 0.002, body_top - 0.09), (0.035, hd + 0.006, body_top + 0.01), metal, "metal",
                       collision="none"))  # the lock plate
    for sx in (-1, 1):  # carrying handles on the ends
        x0, x1 = sorted((sx * hw, sx * (hw + 0.025)))
        parts.append(block((x0, -0.07, body_top - 0.1), (x1, 0.07, body_top - 0.08), metal, "metal"))
    return finish("chest", parts, receptacles=[top_receptacle("top", lid_lo, lid_hi, inset=0.04)],
                  names=["chest", "trunk", "blanket chest", "storage chest"], rooms=["bedroom", "living_room"],
                  placement="wall", front_clearance=0.6, mass=float(width * depth * height * rng.uniform(60, 90)))


# ---------------------------------------------------------------------------------------
# Hallway and living room.


def make_coat_rack(rng: np.random.Generator) -> AssetModel:
    height = rng.uniform(1.7, 1.95)
    color, material = wood_or_metal(rng, P_WOOD)
    pole_r = rng.uniform(0.015, 0.025)
    base = ("disc", "tripod", "cross")[int(rng.integers(3))]
    parts: list[Part] = []
    if base == "disc":
        r = rng.uniform(0.15, 0.2)
        heavy = pick(rng, METALS[2:4]) if rng.random() < 0.5 else color
        parts.append(lathe([(r, 0.0), (r, 0.02), (r * 0.45, 0.045), (pole_r * 1.5, 0.07)], heavy,
                           "metal" if heavy is not color else material, segments=12))
        pole_z0 = 0.02
    elif base == "tripod":
        r, knee = rng.uniform(0.2, 0.27), rng.uniform(0.3, 0.45)
        for k in range(3):
            a = 2 * np.pi * k / 3 + np.pi / 2
            parts.append(_strut((0.0, 0.0, knee), (r * np.cos(a), r * np.sin(a), 0.0), pole_r * 0.8, color,
                                material, segments=6))
        pole_z0 = knee - 0.05
    else:
        r, t = rng.uniform(0.2, 0.26), rng.uniform(0.03, 0.045)
        parts += [block((-r, -t / 2, 0.0), (r, t / 2, t), color, material),
                  block((-t / 2, -r, 0.0), (t / 2, r, t), color, material)]
        pole_z0 = t
    parts.append(rod(0, 0, pole_z0, height - 0.03, pole_r, color, material))
    parts.append(lathe([(pole_r * 1.2, height - 0.04), (pole_r * 1.6, height - 0.015), (0.0, height)], color,
                       material, segments=8))  # the finial
    tiers = 2 if rng.random() < 0.5 else 1
    hooks = int(rng.integers(3, 5)) if tiers == 2 else int(rng.integers(4, 7))
    hook_r = rng.uniform(0.007, 0.011)
    for tier in range(tiers):
        z = height - rng.uniform(0.18, 0.25) - 0.15 * tier
        reach = rng.uniform(0.1, 0.17) * (0.75 if tier else 1.0)
        for k in range(hooks):
            a = 2 * np.pi * (k + 0.5 * tier) / hooks
            c, s = np.cos(a), np.sin(a)
            tip = (reach * c, reach * s, z + reach * rng.uniform(0.5, 0.9))
            parts.append(_strut((0.0, 0.0, z - 0.04), tip, hook_r, color, material, segments=5))
    return finish("coat_rack", parts, names=["coat rack", "coat stand", "hat stand", "hall tree"],
                  rooms=["hallway", "bedroom"], placement="corner", front_clearance=0.4,
                  mass=float(rng.uniform(3, 9)))


def make_console_table(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.8, 1.4), rng.uniform(0.25, 0.4), rng.uniform(0.75, 0.85)
    color, material = wood_or_metal(rng, P_WOOD)
    top_c = color if material == "wood" and rng.random() < 0.7 else pick(rng, WOODS)
    top_t = rng.uniform(0.025, 0.045)
    hw, hd = width / 2, depth / 2
    under = height - top_t
    lo, hi = (-hw, -hd, under), (hw, hd, height)
    parts = [block(lo, hi, top_c, "wood")]
    recs = [top_receptacle("top", lo, hi)]
    inset = rng.uniform(0.0, 0.05)
    shelf = rng.random() < 0.55
    z = rng.uniform(0.12, 0.25)
    if rng.random() < 0.3:  # two slab ends
        t = rng.uniform(0.025, 0.04)
        for sx in (-1, 1):
            x0, x1 = sorted((sx * (hw - inset), sx * (hw - inset - t)))
            parts.append(block((x0, -hd, 0.0), (x1, hd, under), color, material))
        s_lo, s_hi, s_inset = (-hw + inset + t, -hd + 0.01, z), (hw - inset - t, hd - 0.01, z + 0.02), 0.01
    else:
        leg = rng.uniform(0.03, 0.05)
        parts += legs(-hw + inset, hw - inset, -hd + inset / 2, hd - inset / 2, 0.0, under, leg, color, material,
                      round_legs=rng.random() < 0.4)
        s_lo, s_hi, s_inset = (-hw + inset, -hd + inset / 2, z), (hw - inset, hd - inset / 2, z + 0.02), leg
        if rng.random() < 0.6:  # an apron, with drawer fronts in some
            a = inset + leg
            apron = rng.uniform(0.08, 0.12)
            parts.append(block((-hw + a, -hd + inset / 2, under - apron), (hw - a, hd - inset / 2 - 0.01, under),
                               color, material))
            if material == "wood" and rng.random() < 0.6:
                n = 1 if width < 1.1 else 2
                edges = np.linspace(-hw + a, hw - a, n + 1)
                for x0, x1 in zip(edges[:-1], edges[1:]):
                    parts += [block((x0 + 0.01, hd - inset / 2 - 0.01, under - apron + 0.01),
                                    (x1 - 0.01, hd - inset / 2 + 0.005, under - 0.01), shade(color, 1.05), "wood"),
                              _handle("knob", (x0 + x1) / 2, hd - inset / 2 + 0.005, under - apron / 2,
                                      pick(rng, METALS))]
    if shelf:
        parts.append(block(s_lo, s_hi, shade(top_c, 0.95), "wood"))
        recs.append(_between_legs("shelf", s_lo, s_hi, s_inset, under - 0.12 - s_hi[2]))
    return finish("console_table", parts, receptacles=recs,
                  names=["console table", "hall table", "entry table", "sofa table"],
                  rooms=["hallway", "living_room"], placement="wall", front_clearance=0.5,
                  mass=float(rng.uniform(8, 25)))


def make_piano(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(1.42, 1.55), rng.uniform(0.56, 0.66), rng.uniform(1.0, 1.32)
    case = pick(rng, PIANO_FINISHES + WOODS[1:3] + WOODS[5:6], jitter=0.03)
    brass = pick(rng, METALS[4:] + METALS[1:2], jitter=0.03)
    hw, hd = width / 2, depth / 2
    case_d = rng.uniform(0.33, 0.4)
    yc = -hd + case_d  # the case's front; the keys stand out in front of it
    key_top = rng.uniform(0.71, 0.75)
    keys_w = 1.22
    cheek = (width - keys_w) / 2
    lid_t = rng.uniform(0.025, 0.04)
    lid_lo, lid_hi = (-hw - 0.01, -hd, height - lid_t), (hw + 0.01, yc + 0.02, height)
    key_y = hd - rng.uniform(0.0, 0.03)  # the keys' front edge
    keybed_z = key_top - 0.02
    legs_style = rng.random() < 0.4
    parts = [
        block((-hw, -hd, 0.0), (hw, yc, height - lid_t), case, "wood"),
        block(lid_lo, lid_hi, case, "wood"),
        block((-hw + cheek, yc, keybed_z - 0.06), (hw - cheek, key_y, keybed_z), case, "wood"),  # the key bed
        block((-hw + cheek, yc + 0.04, keybed_z), (hw - cheek, key_y, key_top), IVORY, "plastic"),
        block((-hw + cheek, yc, keybed_z), (hw - cheek, yc + 0.04, key_top + 0.07), case, "wood"),  # fallboard
        block((-0.4, yc, key_top + 0.14), (0.4, yc + 0.06, key_top + 0.16), shade(case, 0.9), "wood"),  # music rail
        block((-hw + cheek + 0.04, yc, key_top + 0.16), (hw - cheek - 0.04, yc + 0.012, height - lid_t - 0.06),
              shade(case, rng.uniform(0.8, 0.92)), "wood", collision="none"),  # the upper front panel
    ]
    for sx in (-1, 1):  # the cheeks flanking the keys, on legs in some
        x0, x1 = sorted((sx * hw, sx * (hw - cheek)))
        z0 = keybed_z - 0.1 if legs_style else 0.0
        parts.append(block((x0, yc, z0), (x1, hd, key_top + 0.05), case, "wood"))
        if legs_style:
            xm = (x0 + x1) / 2
            parts.append(rod(xm, hd - 0.05, 0.0, z0, 0.025, case, "wood", segments=6, radius_top=0.035))
    # Black keys: a block for each group of two or three over the 52 white keys from A0.
    w = keys_w / 52
    x_keys = -keys_w / 2
    groups = [(0, 1)] + [(c, n) for octave in range(7) for c, n in ((2 + 7 * octave, 2), (5 + 7 * octave, 3))]
    for first, n in groups:
        x0 = x_keys + (first + 1) * w - 0.3 * w
        x1 = x_keys + (first + n) * w + 0.3 * w
        parts.append(block((x0, yc + 0.04, key_top), (x1, yc + 0.04 + 0.09, key_top + 0.012), EBONY, "plastic",
                           collision="none"))
    for k in (-1, 0, 1):  # the pedals
        x = k * 0.07
        parts.append(block((x - 0.018, yc, 0.05), (x + 0.018, yc + 0.12, 0.065), brass, "metal", collision="none"))
    return finish("piano", parts, receptacles=[top_receptacle("top", lid_lo, lid_hi, inset=0.05)],
                  names=["piano", "upright piano"], rooms=["living_room"], placement="wall",
                  front_clearance=0.9, mass=float(rng.uniform(180, 280)))


FACTORIES = {
    "ottoman": make_ottoman,
    "bench": make_bench,
    "stool": make_stool,
    "office_chair": make_office_chair,
    "filing_cabinet": make_filing_cabinet,
    "storage_cabinet": make_storage_cabinet,
    "shoe_rack": make_shoe_rack,
    "coat_rack": make_coat_rack,
    "sideboard": make_sideboard,
    "console_table": make_console_table,
    "piano": make_piano,
    "chest": make_chest,
}

register_builtins(FACTORIES)
