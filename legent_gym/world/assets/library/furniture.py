"""Built-in furniture: parametric, seeded, low-poly, registered on import.

Each factory takes the registry's generator and returns an :class:`AssetModel` in the asset
frame (z up, footprint centred on the origin on the floor, front facing +y). Sizes follow
common retail ranges. Surfaces that hold things are solid boxes whose top is exactly the
receptacle height. Doors (wardrobe, fridge, kitchen counter, some tv stands) hinge about a
vertical front edge and swing toward +y; drawers (dresser, nightstand, most desks, some
kitchen counters and tv stands) slide along +y; closed is joint value 0.
"""

from __future__ import annotations

import numpy as np

from legent_gym.world.assets.library.common import (
    APPLIANCES,
    BEDDING,
    CERAMICS,
    COUNTERTOPS,
    FABRICS,
    FOLIAGE,
    METALS,
    RGBA,
    SCREEN,
    WHITE,
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
    upholstery,
    wood_or_metal,
)
from legent_gym.world.assets.model import AssetModel, Part, Receptacle, sphere_part

#: How often a frame is wood rather than metal, and a cover leather rather than fabric.
P_WOOD, P_LEATHER = 0.7, 0.25


# ---------------------------------------------------------------------------------------
# Handles of the doors and drawers.


def _door_bar(rgba: RGBA) -> Handle:
    """A vertical bar pull, 40 % of the door's height and at most 30 cm long."""
    def make(x: float, y: float, z: float, height: float) -> list[Part]:
        hl = min(0.3, 0.4 * height)
        return [block((x - 0.012, y, z - hl / 2), (x + 0.012, y + 0.028, z + hl / 2), rgba, "metal")]
    return make


def _drawer_bar(rgba: RGBA) -> Handle:
    """A 12 cm bar pull across a drawer front."""
    def make(x: float, y: float, z: float, height: float) -> list[Part]:
        return [block((x - 0.06, y, z - 0.01), (x + 0.06, y + 0.025, z + 0.01), rgba, "metal")]
    return make


def _flat_pull(rgba: RGBA, length: float, depth: float, *, vertical: bool = False, width: float = 0.016) -> Handle:
    """A flat bar pull ``length`` long (across, or up the front), ``width`` wide, standing
    ``depth`` out of the front."""
    def make(x: float, y: float, z: float, height: float) -> list[Part]:
        hx, hz = (width / 2, length / 2) if vertical else (length / 2, width / 2)
        return [block((x - hx, y, z - hz), (x + hx, y + depth, z + hz), rgba, "metal")]
    return make


# ---------------------------------------------------------------------------------------
# Bedroom.


def make_bed(rng: np.random.Generator) -> AssetModel:
    width, length = rng.uniform(1.4, 2.0), rng.uniform(1.95, 2.2)
    wood, linen, cover = pick(rng, WOODS), pick(rng, BEDDING), pick(rng, BEDDING + FABRICS)
    head_t, head_h = rng.uniform(0.05, 0.08), rng.uniform(0.9, 1.25)
    foot_t = rng.uniform(0.03, 0.05) if rng.random() < 0.4 else 0.0
    leg_h = rng.uniform(0.05, 0.15)
    frame_top = leg_h + rng.uniform(0.12, 0.2)
    mattress_top = frame_top + rng.uniform(0.18, 0.28)
    hw, y0, y1 = width / 2, -length / 2 + head_t, length / 2 - foot_t
    mw = hw - 0.02
    parts = [
        block((-hw, -length / 2, 0.0), (hw, y0, head_h), wood, "wood"),
        block((-hw, y0, leg_h), (hw, y1, frame_top), wood, "wood"),
        *legs(-hw, hw, y0, y1, 0.0, leg_h, 0.07, shade(wood, 0.8), "wood"),
        block((-mw, y0 + 0.01, frame_top), (mw, y1 - 0.02, mattress_top), linen, "fabric"),
    ]
    if foot_t:
        parts.append(block((-hw, y1, 0.0), (hw, length / 2, mattress_top - 0.05), wood, "wood"))
    pillows = 2 if width >= 1.5 else 1
    pillow_d = rng.uniform(0.3, 0.42)
    pw = (2 * mw - 0.1) / pillows
    for i in range(pillows):
        x = -mw + 0.05 + pw * i
        pillow_top = mattress_top + rng.uniform(0.1, 0.14)
        parts.append(block((x + 0.02, y0 + 0.05, mattress_top), (x + pw - 0.02, y0 + 0.05 + pillow_d, pillow_top),
                           linen, "fabric"))
    # The blanket drapes over the foot part of the mattress; its top is the receptacle.
    blanket_lo = (-mw - 0.015, y0 + 0.05 + pillow_d + rng.uniform(0.05, 0.25), mattress_top - 0.12)
    blanket_hi = (mw + 0.015, y1 - 0.005, mattress_top + 0.03)
    parts.append(block(blanket_lo, blanket_hi, cover, "fabric"))
    return finish("bed", parts, receptacles=[top_receptacle("top", blanket_lo, blanket_hi)],
                  names=["bed"], rooms=["bedroom"], placement="wall", front_clearance=0.6,
                  mass=float(rng.uniform(60, 110)))


def make_wardrobe(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.8, 1.6), rng.uniform(0.5, 0.65), rng.uniform(1.8, 2.2)
    wood, handle = pick(rng, WOODS), pick(rng, METALS)
    t, door_t, plinth = 0.02, 0.02, rng.uniform(0.05, 0.1)
    hw, hd = width / 2, depth / 2
    yf = hd - door_t  # carcass front; the doors lie in front of it
    inner, rail_y = shade(wood, 0.9), (yf - hd) / 2
    parts = [
        block((-hw, -hd, 0.0), (-hw + t, yf, height), wood, "wood"),
        block((hw - t, -hd, 0.0), (hw, yf, height), wood, "wood"),
        block((-hw + t, -hd, height - t), (hw - t, yf, height), wood, "wood"),
        block((-hw + t, -hd, plinth), (hw - t, yf, plinth + t), inner, "wood"),
        block((-hw + t, -hd + 0.02, 0.0), (hw - t, yf - 0.02, plinth), shade(wood, 0.7), "wood"),
        block((-hw + t, -hd, plinth + t), (hw - t, -hd + 0.01, height - t), inner, "wood"),
        block((-hw + t, -hd + 0.01, height - 0.35), (hw - t, yf - 0.03, height - 0.33), inner, "wood"),
        block((-hw + t, rail_y - 0.01, height - 0.45), (hw - t, rail_y + 0.01, height - 0.43), handle, "metal"),
    ]
    doors = 2 if width >= 0.9 else 1
    edges = np.linspace(-hw, hw, doors + 1)
    moving = [hinged_door(f"door_{i}", edges[i] + 0.002, edges[i + 1] - 0.002, yf, plinth, height - 0.005,
                          hinge_left=(i == 0), rgba=wood, material="wood", handle=_door_bar(handle),
                          thickness=door_t, handle_z=1.05)
              for i in range(doors)]
    door_w = float(edges[1] - edges[0])
    return finish("wardrobe", parts, moving=moving, names=["wardrobe", "closet", "armoire"],
                  rooms=["bedroom", "hallway"], placement="wall",
                  front_clearance=max(0.8, door_w + 0.1), mass=float(rng.uniform(60, 120)))


def _cabinet_shell(width: float, depth: float, floor_z: float, base_z: float, top_z: float,
                   wood: RGBA, top_t: float = 0.025) -> tuple[list[Part], tuple]:
    """Sides, back, base board (floor_z..base_z) and top of a drawer cabinet.

    Returns the parts and the top's (lo, hi) corners.
    """
    hw, hd, t = width / 2, depth / 2, 0.018
    top_lo, top_hi = (-hw - 0.01, -hd, top_z), (hw + 0.01, hd + 0.01, top_z + top_t)
    parts = [
        block(top_lo, top_hi, wood, "wood"),
        block((-hw, -hd, floor_z), (-hw + t, hd, top_z), wood, "wood"),
        block((hw - t, -hd, floor_z), (hw, hd, top_z), wood, "wood"),
        block((-hw + t, -hd, floor_z), (hw - t, -hd + 0.01, top_z), shade(wood, 0.85), "wood"),
        block((-hw + t, -hd + 0.01, floor_z), (hw - t, hd - 0.02, base_z), shade(wood, 0.75), "wood"),
    ]
    return parts, (top_lo, top_hi)


def make_dresser(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.8, 1.5), rng.uniform(0.42, 0.55), rng.uniform(0.75, 1.1)
    wood, handle = pick(rng, WOODS), pick(rng, METALS)
    front = wood if rng.random() < 0.6 else pick(rng, WOODS)
    base_z, top_t = rng.uniform(0.06, 0.12), 0.025
    top_z = height - top_t
    parts, top_box = _cabinet_shell(width, depth, 0.0, base_z, top_z, wood, top_t=top_t)
    n = 3 if height < 0.9 else 4
    slots = np.linspace(base_z, top_z, n + 1)
    hw, hd, t = width / 2, depth / 2, 0.018
    moving, recs = [], [top_receptacle("top", *top_box)]
    for i in range(n):
        link, rec = drawer(f"drawer_{i}", -hw + t, hw - t, hd, depth - 0.03, slots[i], slots[i + 1],
                           front=front, body=shade(wood, 0.9), material="wood", handle=_drawer_bar(handle))
        moving.append(link)
        recs.append(rec)
    return finish("dresser", parts, moving=moving, receptacles=recs,
                  names=["dresser", "chest of drawers", "drawers"],
                  rooms=["bedroom", "living_room", "dining_room", "hallway"],
                  placement="wall", front_clearance=max(0.8, 0.8 * depth + 0.4),
                  mass=float(rng.uniform(40, 80)))


def make_nightstand(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.4, 0.6), rng.uniform(0.35, 0.45), rng.uniform(0.5, 0.65)
    wood, handle = pick(rng, WOODS), pick(rng, METALS)
    hw, hd, t, top_t = width / 2, depth / 2, 0.018, 0.022
    leg_h = rng.uniform(0.04, 0.15)
    top_z = height - top_t
    drawer_z = top_z - rng.uniform(0.12, 0.16)
    # The cabinet stands on legs; its base board is an open shelf under the drawer.
    parts, top_box = _cabinet_shell(width, depth, leg_h, leg_h + t, top_z, wood, top_t=top_t)
    shelf_lo, shelf_hi = (-hw + t, -hd + 0.01, leg_h), (hw - t, hd - 0.02, leg_h + t)
    parts.append(block((-hw + t, -hd + 0.01, drawer_z - t), (hw - t, hd, drawer_z), shade(wood, 0.9), "wood"))
    parts += legs(-hw, hw, -hd, hd, 0.0, leg_h, 0.04, shade(wood, 0.8), "wood")
    link, inner = drawer("drawer_0", -hw + t, hw - t, hd, depth - 0.03, drawer_z, top_z,
                         front=wood, body=shade(wood, 0.9), material="wood", handle=_drawer_bar(handle))
    recs = [top_receptacle("top", *top_box), inner,
            top_receptacle("shelf", shelf_lo, shelf_hi, clearance=drawer_z - t - shelf_hi[2])]
    return finish("nightstand", parts, moving=[link], receptacles=recs,
                  names=["nightstand", "bedside table", "night table"], rooms=["bedroom"],
                  placement="wall", front_clearance=0.5, mass=float(rng.uniform(10, 20)))


# ---------------------------------------------------------------------------------------
# Living room.


def _seating(rng: np.random.Generator, width: float, seats: int) -> tuple[list[Part], Receptacle]:
    """A sofa-like seat: legs, base, backrest, arms, seat and back cushions."""
    depth, height = rng.uniform(0.8, 0.98), rng.uniform(0.75, 0.95)
    cover, material = upholstery(rng, P_LEATHER)
    leg_c, leg_m = wood_or_metal(rng, P_WOOD)
    leg_h = rng.uniform(0.05, 0.14)
    base_top = leg_h + rng.uniform(0.17, 0.22)
    seat_h = base_top + rng.uniform(0.1, 0.14)
    arm_w, arm_h = rng.uniform(0.1, 0.2), seat_h + rng.uniform(0.15, 0.25)
    back_t, cushion_t = rng.uniform(0.15, 0.2), rng.uniform(0.1, 0.15)
    hw, hd = width / 2, depth / 2
    xi, yb = hw - arm_w, -hd + back_t
    cushion = shade(cover, 1.06)
    parts = [
        *legs(-hw, hw, -hd, hd, 0.0, leg_h, 0.05, leg_c, leg_m, round_legs=rng.random() < 0.5),
        block((-hw, -hd, leg_h), (hw, hd, base_top), cover, material),
        block((-hw, -hd, base_top), (hw, yb, height), cover, material),
        block((-hw, yb, base_top), (-xi, hd, arm_h), cover, material),
        block((xi, yb, base_top), (hw, hd, arm_h), cover, material),
    ]
    edges = np.linspace(-xi, xi, seats + 1)
    for a, b in zip(edges[:-1], edges[1:]):
        parts.append(block((a, yb, base_top), (b, hd, seat_h), cushion, material))
        parts.append(block((a, yb, seat_h), (b, yb + cushion_t, height - 0.06), cushion, material))
    seat = top_receptacle("seat", (-xi, yb + cushion_t, 0.0), (xi, hd, seat_h))
    return parts, seat


def make_sofa(rng: np.random.Generator) -> AssetModel:
    width = rng.uniform(1.6, 2.4)
    parts, seat = _seating(rng, width, 2 if width < 1.95 else 3)
    return finish("sofa", parts, receptacles=[seat], names=["sofa", "couch"], rooms=["living_room", "office"],
                  placement="wall", front_clearance=0.6, mass=float(rng.uniform(40, 90)))


def make_armchair(rng: np.random.Generator) -> AssetModel:
    parts, seat = _seating(rng, rng.uniform(0.72, 0.95), 1)
    return finish("armchair", parts, receptacles=[seat], names=["armchair", "arm chair", "easy chair"],
                  rooms=["living_room", "bedroom", "office"], placement="corner", front_clearance=0.6,
                  mass=float(rng.uniform(20, 40)))


def _table(rng: np.random.Generator, width: float, depth: float, height: float, *,
           apron: bool = False, shelf: bool = False) -> tuple[list[Part], list[Receptacle]]:
    """A top on four legs, optionally with an apron under the top or a shelf low between the legs."""
    color, material = wood_or_metal(rng, P_WOOD)
    top_c = color if material == "wood" and rng.random() < 0.7 else pick(rng, WOODS)
    top_t, leg = rng.uniform(0.025, 0.05), rng.uniform(0.04, 0.07)
    hw, hd = width / 2, depth / 2
    inset = rng.uniform(0.0, 0.06)
    under = height - top_t
    lo, hi = (-hw, -hd, under), (hw, hd, height)
    parts = [block(lo, hi, top_c, "wood"),
             *legs(-hw + inset, hw - inset, -hd + inset, hd - inset, 0.0, under, leg, color, material,
                   round_legs=rng.random() < 0.4)]
    recs = [top_receptacle("top", lo, hi)]
    if apron:
        a = inset + leg / 2 - 0.01
        parts += [block((-hw + a, -hd + a, under - 0.08), (hw - a, -hd + a + 0.02, under), color, material),
                  block((-hw + a, hd - a - 0.02, under - 0.08), (hw - a, hd - a, under), color, material)]
    if shelf:
        # The shelf spans the legs' outer rectangle; its receptacle keeps clear of the legs.
        z = rng.uniform(0.08, 0.14)
        s_lo, s_hi = (-hw + inset, -hd + inset, z), (hw - inset, hd - inset, z + 0.02)
        parts.append(block(s_lo, s_hi, top_c, "wood"))
        recs.append(top_receptacle("shelf", s_lo, s_hi, inset=leg + 0.02, clearance=under - s_hi[2]))
    return parts, recs


def make_dining_table(rng: np.random.Generator) -> AssetModel:
    width, depth = rng.uniform(1.2, 2.0), rng.uniform(0.75, 1.0)
    parts, recs = _table(rng, width, depth, rng.uniform(0.72, 0.78), apron=rng.random() < 0.6)
    return finish("dining_table", parts, receptacles=recs, names=["table", "dining table"],
                  rooms=["dining_room", "kitchen", "living_room"], placement="middle", front_clearance=0.7,
                  mass=float(rng.uniform(25, 60)))


def make_coffee_table(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.9, 1.3), rng.uniform(0.5, 0.7), rng.uniform(0.38, 0.48)
    parts, recs = _table(rng, width, depth, height, shelf=rng.random() < 0.5)
    return finish("coffee_table", parts, receptacles=recs, names=["coffee table", "table"],
                  rooms=["living_room"], placement="middle", front_clearance=0.4,
                  mass=float(rng.uniform(12, 30)))


def make_side_table(rng: np.random.Generator) -> AssetModel:
    size, height = rng.uniform(0.4, 0.6), rng.uniform(0.45, 0.65)
    if rng.random() < 0.5:
        parts, recs = _table(rng, size, size * rng.uniform(0.85, 1.0), height)
    else:
        color, material = wood_or_metal(rng, P_WOOD)
        r, top_t, seg = size / 2, rng.uniform(0.025, 0.04), 12
        parts = [rod(0, 0, height - top_t, height, r, color, material, segments=seg),
                 rod(0, 0, 0.02, height - top_t, rng.uniform(0.02, 0.035), color, material),
                 rod(0, 0, 0.0, 0.02, r * rng.uniform(0.5, 0.7), color, material, segments=10)]
        recs = [round_top("top", r, seg, height, inset=0.03)]
    return finish("side_table", parts, receptacles=recs, names=["side table", "end table", "table"],
                  rooms=["living_room", "bedroom", "hallway", "office"], placement="corner", front_clearance=0.3,
                  mass=float(rng.uniform(5, 12)))


def make_bookshelf(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.6, 1.2), rng.uniform(0.25, 0.4), rng.uniform(1.2, 2.0)
    wood = pick(rng, WOODS)
    t, plinth = rng.uniform(0.018, 0.025), rng.uniform(0.04, 0.08)
    hw, hd = width / 2, depth / 2
    back = -hd + 0.008
    parts = [
        block((-hw, -hd, 0.0), (-hw + t, hd, height), wood, "wood"),
        block((hw - t, -hd, 0.0), (hw, hd, height), wood, "wood"),
        block((-hw + t, -hd, height - t), (hw - t, hd, height), wood, "wood"),
        block((-hw + t, -hd, plinth), (hw - t, -hd + 0.008, height - t), shade(wood, 0.85), "wood"),
        block((-hw + t, -hd + 0.008, 0.0), (hw - t, hd - 0.015, plinth), shade(wood, 0.75), "wood"),
    ]
    boards = int(np.clip(round((height - plinth) / 0.36), 3, 6))  # shelves incl. the bottom one
    zs = np.linspace(plinth, height - t, boards + 1)[:-1]
    recs = []
    for i, z in enumerate(zs):
        lo, hi = (-hw + t, back, z), (hw - t, hd - 0.005, z + t)
        parts.append(block(lo, hi, wood, "wood"))
        ceiling = zs[i + 1] if i + 1 < len(zs) else height - t
        recs.append(top_receptacle(f"shelf_{i}", lo, hi, clearance=float(ceiling - hi[2])))
    if height < 1.4:
        recs.append(top_receptacle("top", (-hw, -hd, 0.0), (hw, hd, height)))
    return finish("bookshelf", parts, receptacles=recs, names=["bookshelf", "bookcase", "shelf", "shelves"],
                  rooms=["living_room", "office", "bedroom", "dining_room"], placement="wall", front_clearance=0.6,
                  mass=float(rng.uniform(25, 60)))


def make_tv_stand(rng: np.random.Generator) -> AssetModel:
    """A low cabinet on legs with an open middle compartment between two side ones: open on
    half of them, else closed by hinged doors (two on a wide side; a shelf behind them) or a
    drawer."""
    width, depth, height = rng.uniform(1.0, 1.8), rng.uniform(0.35, 0.5), rng.uniform(0.4, 0.6)
    wood, handle = pick(rng, WOODS), pick(rng, METALS)
    front = wood if rng.random() < 0.6 else pick(rng, WOODS)
    t, leg_h = 0.02, rng.uniform(0.05, 0.12)
    hw, hd = width / 2, depth / 2
    top_lo, top_hi = (-hw, -hd, height - t), (hw, hd, height)
    mid = width * rng.uniform(0.18, 0.26)  # half width of the open middle compartment
    mass = float(rng.uniform(20, 45))
    u = rng.random()
    sides = "open" if u < 0.5 else "doors" if u < 0.75 else "drawers"
    bottom_lo, bottom_hi = (-hw, -hd, leg_h), (hw, hd - 0.02, leg_h + t)
    # Open sides: the top reaches as far forward as the fronts' handles would.
    parts = [
        block(top_lo, (hw, hd + 0.02, height) if sides == "open" else top_hi, wood, "wood"),
        block(bottom_lo, bottom_hi, wood, "wood"),
        block((-hw, -hd, leg_h + t), (-hw + t, hd - 0.02, height - t), wood, "wood"),
        block((hw - t, -hd, leg_h + t), (hw, hd - 0.02, height - t), wood, "wood"),
        block((-hw + t, -hd, leg_h + t), (hw - t, -hd + 0.01, height - t), shade(wood, 0.85), "wood"),
        block((-mid - t, -hd + 0.01, leg_h + t), (-mid, hd - 0.02, height - t), wood, "wood"),
        block((mid, -hd + 0.01, leg_h + t), (mid + t, hd - 0.02, height - t), wood, "wood"),
        *legs(-hw, hw, -hd, hd - 0.02, 0.0, leg_h, 0.05, shade(wood, 0.7), "wood"),
    ]
    clearance = height - t - bottom_hi[2]
    recs = [top_receptacle("top", top_lo, top_hi),
            top_receptacle("shelf", (-mid, bottom_lo[1] + 0.01, 0.0), (mid, bottom_hi[1], bottom_hi[2]),
                           clearance=clearance)]
    moving = []
    # The open sides are no receptacles (yet): small objects would be spread over two more
    # surfaces, and every generated house with such a stand would change.
    for k, sign in enumerate((-1, 1)):
        x0, x1 = sorted((sign * (mid + t), sign * hw))  # the side compartment, its side board included
        if sides == "drawers":
            link, rec = drawer(f"drawer_{k}", x0, x1, hd, depth - 0.03, leg_h + t, height - t, front=front,
                               body=shade(wood, 0.9), material="wood", handle=_flat_pull(handle, 0.12, 0.02),
                               side_clear=t + 0.008)
            moving.append(link)
            recs.append(rec)
        elif sides == "doors":  # a shelf behind one door hinged at the outer end, or a pair on a wide side
            recs.append(top_receptacle("shelf_left" if sign < 0 else "shelf_right",
                                       (x0 + (t if sign < 0 else 0.0), bottom_lo[1] + 0.01, 0.0),
                                       (x1 - (0.0 if sign < 0 else t), bottom_hi[1], bottom_hi[2]),
                                       clearance=clearance))
            edges = [x0 + 0.003, x1 - 0.003]
            hinges = [sign < 0]
            if x1 - x0 > 0.406:
                edges.insert(1, (x0 + x1) / 2)
                hinges = [True, False]
            for i, hinge_left in enumerate(hinges):
                a = edges[i] + (0.002 if i else 0.0)
                b = edges[i + 1] - (0.002 if i + 1 < len(hinges) else 0.0)
                moving.append(hinged_door(f"door_{len(moving)}", a, b, hd, leg_h + 0.003, height - t - 0.003,
                                          hinge_left=hinge_left, rgba=front, material="wood",
                                          handle=_flat_pull(handle, 0.12, 0.02, vertical=True, width=0.02),
                                          handle_z=(leg_h + height) / 2, handle_inset=0.057, hinge_at_front=True))
    return finish("tv_stand", parts, moving=moving, receptacles=recs,
                  names=["tv stand", "tv cabinet", "media console"], rooms=["living_room", "bedroom"],
                  placement="wall", front_clearance=0.5, mass=mass)


def make_tv(rng: np.random.Generator) -> AssetModel:
    width = rng.uniform(0.72, 1.45)  # about 32" to 65"
    panel_h, panel_d = width * 9 / 16 + 0.03, rng.uniform(0.03, 0.06)
    frame = pick(rng, ((0.08, 0.08, 0.09), (0.2, 0.2, 0.22), (0.6, 0.6, 0.62)), jitter=0.02)
    lift = rng.uniform(0.05, 0.1)
    bezel = 0.012
    hw = width / 2
    parts = [
        block((-hw, -panel_d / 2, lift), (hw, panel_d / 2, lift + panel_h), frame, "plastic"),
        block((-hw + bezel, panel_d / 2, lift + bezel), (hw - bezel, panel_d / 2 + 0.002, lift + panel_h - bezel),
              SCREEN, "glass", collision="none"),
    ]
    base_d = rng.uniform(0.18, 0.26)
    if rng.random() < 0.5:  # centre pedestal
        bw = rng.uniform(0.25, 0.4)
        parts += [block((-bw / 2, -base_d / 2, 0.0), (bw / 2, base_d / 2, 0.015), frame, "metal"),
                  block((-0.04, -panel_d / 2 - 0.03, 0.015), (0.04, -panel_d / 2, lift + 0.15), frame, "metal")]
    else:  # two feet near the ends
        for x in (-hw + 0.12, hw - 0.12):
            parts.append(block((x - 0.03, -base_d / 2, 0.0), (x + 0.03, base_d / 2, lift + 0.02), frame, "metal"))
    return finish("tv", parts, names=["tv", "television", "tv set"], rooms=["living_room", "bedroom"],
                  placement="surface", front_clearance=0.5, mass=float(6 + 14 * (width - 0.72) / 0.73))


def make_plant(rng: np.random.Generator) -> AssetModel:
    pot_r, pot_h = rng.uniform(0.1, 0.2), rng.uniform(0.18, 0.4)
    pot = pick(rng, CERAMICS)
    leaves = pick(rng, FOLIAGE, jitter=0.12)
    rim = pot_r * 0.9
    parts = [lathe([(pot_r * 0.72, 0.0), (pot_r, pot_h), (rim, pot_h), (rim, pot_h - 0.03)], pot, "ceramic"),
             rod(0, 0, pot_h - 0.03, pot_h - 0.02, rim * 0.95, (0.3, 0.22, 0.15, 1.0), "plain", collision="none")]
    if rng.random() < 0.5:  # a bush sitting in the pot
        for _ in range(3):
            r = pot_r * rng.uniform(1.0, 1.6)
            c = (rng.uniform(-0.5, 0.5) * pot_r, rng.uniform(-0.5, 0.5) * pot_r, pot_h + r * rng.uniform(0.6, 1.4))
            parts.append(sphere_part(c, r, shade(leaves, rng.uniform(0.85, 1.15)), collision="none", material="plain"))
    else:  # a small tree: trunk and a crown
        top = rng.uniform(0.9, 1.5)
        parts.append(rod(0, 0, pot_h - 0.03, top, 0.02, (0.4, 0.3, 0.2, 1.0), "wood", collision="none"))
        for k in range(2):
            r = rng.uniform(0.2, 0.32)
            parts.append(sphere_part((rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), top - k * r * 0.9),
                                     r, shade(leaves, 1.0 + 0.1 * k), scale=(1.0, 1.0, 1.2),
                                     collision="none", material="plain"))
    return finish("plant", parts, names=["plant", "potted plant", "houseplant"],
                  rooms=["living_room", "office", "hallway", "bedroom", "dining_room", "kitchen"],
                  placement="corner", front_clearance=0.3, mass=float(rng.uniform(3, 15)))


def make_floor_lamp(rng: np.random.Generator) -> AssetModel:
    height = rng.uniform(1.4, 1.8)
    metal = pick(rng, METALS)
    shade_c = pick(rng, ((0.95, 0.93, 0.86), (0.9, 0.85, 0.72), (0.85, 0.85, 0.85), (0.35, 0.35, 0.37)))
    base_r, shade_r, shade_h = rng.uniform(0.12, 0.17), rng.uniform(0.16, 0.24), rng.uniform(0.25, 0.35)
    parts = [rod(0, 0, 0.0, 0.03, base_r, metal, "metal", segments=10),
             rod(0, 0, 0.03, height - shade_h * 0.5, 0.013, metal, "metal"),
             rod(0, 0, height - shade_h, height, shade_r, shade_c, "fabric", segments=10,
                 radius_top=shade_r * rng.uniform(0.65, 0.85))]
    return finish("floor_lamp", parts, names=["floor lamp", "lamp", "standing lamp"],
                  rooms=["living_room", "bedroom", "office"], placement="corner", front_clearance=0.3,
                  mass=float(rng.uniform(4, 9)))


# ---------------------------------------------------------------------------------------
# Office and dining.


def make_desk(rng: np.random.Generator) -> AssetModel:
    """A top on legs, with a drawer pedestal on one side (two legs on the other) half the time,
    else four legs and, on some, one shallow drawer under the middle of the top; the space
    between stays clear for the knees of whoever sits at it."""
    width, depth, height = rng.uniform(1.0, 1.6), rng.uniform(0.55, 0.75), rng.uniform(0.72, 0.76)
    color, material = wood_or_metal(rng, P_WOOD)
    top_c, handle = pick(rng, WOODS), pick(rng, METALS)
    top_t, leg, t = rng.uniform(0.025, 0.04), 0.05, 0.018
    hw, hd = width / 2, depth / 2
    lo, hi = (-hw, -hd, height - top_t), (hw, hd, height)
    under = height - top_t
    parts = [block(lo, hi, top_c, "wood")]
    moving, recs = [], [top_receptacle("top", lo, hi)]
    pedestal = rng.random() < 0.5
    side = (1 if rng.random() < 0.5 else -1) if pedestal else 0
    mass = float(rng.uniform(20, 45))
    if pedestal:  # a drawer pedestal on one side, two legs on the other
        px0, px1 = sorted((side * hw, side * (hw - 0.4)))
        knee = (-hw + 0.05, px0) if side > 0 else (px1, hw - 0.05)  # the back panel spans the knee space
        parts += [block((knee[0], -hd + 0.02, under - 0.3), (knee[1], -hd + 0.04, under), color, material),
                  block((px0, -hd, 0.0), (px0 + t, hd - 0.02, under), top_c, "wood"),
                  block((px1 - t, -hd, 0.0), (px1, hd - 0.02, under), top_c, "wood"),
                  block((px0 + t, -hd, 0.0), (px1 - t, -hd + 0.01, under), shade(top_c, 0.85), "wood")]
        n = 2 if rng.random() < 0.4 else 3
        heights = np.linspace(0.0, under, n + 1)
        for i in range(n):
            link, rec = drawer(f"drawer_{i}", px0, px1, hd, depth - 0.03, heights[i], heights[i + 1],
                               front=shade(top_c, 0.9), body=shade(top_c, 0.8), material="wood",
                               handle=_flat_pull(handle, 0.1, 0.02), side_clear=t + 0.008)
            moving.append(link)
            recs.append(rec)
        lx0, lx1 = sorted((-side * hw, -side * (hw - leg)))
        for y0, y1 in ((-hd, -hd + leg), (hd - leg, hd)):
            parts.append(block((lx0, y0, 0.0), (lx1, y1, under), color, material))
    else:
        parts += [block((-hw + 0.05, -hd + 0.02, under - 0.3), (hw - 0.05, -hd + 0.04, under), color, material),
                  *legs(-hw, hw, -hd, hd, 0.0, under, leg, color, material)]
        if rng.random() < 0.4:  # one shallow drawer under the middle, between two runners
            dw, dh, yf = min(0.6, 0.45 * width), 0.1, hd - 0.02
            for x0, x1 in ((-dw / 2 - t, -dw / 2), (dw / 2, dw / 2 + t)):
                parts.append(block((x0, -hd + 0.04, under - dh), (x1, yf, under), color, material))
            link, rec = drawer("drawer_0", -dw / 2, dw / 2, yf, yf + hd - 0.05, under - dh, under, front=top_c,
                               body=shade(top_c, 0.85), material="wood", handle=_flat_pull(handle, 0.1, 0.015))
            moving.append(link)
            recs.append(rec)
    return finish("desk", parts, moving=moving, receptacles=recs,
                  names=["desk", "writing desk", "work desk"], rooms=["office", "bedroom"],
                  placement="wall", front_clearance=0.7, mass=mass)


def make_chair(rng: np.random.Generator) -> AssetModel:
    width, depth = rng.uniform(0.4, 0.5), rng.uniform(0.42, 0.52)
    seat_h, back_h = rng.uniform(0.43, 0.48), rng.uniform(0.8, 1.0)
    color, material = wood_or_metal(rng, P_WOOD)
    leg, seat_t = rng.uniform(0.03, 0.045), rng.uniform(0.025, 0.04)
    hw, hd = width / 2, depth / 2
    padded = rng.random() < 0.5
    seat_top = seat_h - (0.03 if padded else 0.0)
    lo, hi = (-hw, -hd, seat_top - seat_t), (hw, hd, seat_top)
    parts = [block(lo, hi, color, material)]
    for sx in (-1, 1):
        x0, x1 = sorted((sx * hw, sx * (hw - leg)))
        parts += [block((x0, hd - leg, 0.0), (x1, hd, seat_top - seat_t), color, material),
                  block((x0, -hd, 0.0), (x1, -hd + leg, back_h), color, material)]  # back leg and post
    for z in np.linspace(back_h - 0.1, seat_top + 0.15, 2 if rng.random() < 0.5 else 1):
        parts.append(block((-hw + leg, -hd + 0.005, z - 0.04), (hw - leg, -hd + leg - 0.005, z + 0.04), color, material))
    if padded:
        cushion, cm = upholstery(rng, P_LEATHER)
        lo, hi = (-hw + 0.01, -hd + leg, seat_top), (hw - 0.01, hd - 0.01, seat_h)
        parts.append(block(lo, hi, cushion, cm))
    seat = top_receptacle("seat", (lo[0], -hd + leg, 0.0), hi)  # clear of the back posts
    return finish("chair", parts, receptacles=[seat],
                  names=["chair", "dining chair"], rooms=["dining_room", "kitchen", "office", "bedroom"],
                  placement="middle", front_clearance=0.4, mass=float(rng.uniform(4, 9)))


# ---------------------------------------------------------------------------------------
# Kitchen and bathroom.


def _base_cabinet(width: float, depth: float, top_z: float, doors: int, body: RGBA, front: RGBA,
                  handle: RGBA) -> list[Part]:
    """A sink's base unit up to ``top_z``: toe kick, an open box, doors and handles (fixed: the
    basin and its pipes fill it)."""
    hw, hd, kick = width / 2, depth / 2, 0.1
    yc = hd - 0.045  # the doors stand in front of the body, behind the countertop's edge
    t = 0.018
    parts = [block((-hw + 0.01, -hd, 0.0), (hw - 0.01, yc - 0.05, kick), shade(body, 0.5), "wood"),
             block((-hw, -hd, kick), (-hw + t, yc, top_z), body, "wood"),
             block((hw - t, -hd, kick), (hw, yc, top_z), body, "wood"),
             block((-hw + t, -hd, kick), (hw - t, -hd + t, top_z), body, "wood"),
             block((-hw + t, -hd + t, kick), (hw - t, yc, kick + t), body, "wood")]
    edges = np.linspace(-hw, hw, doors + 1)
    for a, b in zip(edges[:-1], edges[1:]):
        parts.append(block((a + 0.002, yc, kick + 0.003), (b - 0.002, yc + 0.02, top_z - 0.003), front, "wood"))
        hz = top_z - 0.08
        parts.append(block(((a + b) / 2 - 0.06, yc + 0.02, hz - 0.008), ((a + b) / 2 + 0.06, yc + 0.04, hz + 0.008),
                           handle, "metal"))
    return parts


def make_kitchen_counter(rng: np.random.Generator) -> AssetModel:
    """A base cabinet under a stone top: a row of hinged doors, with a shelf half way up
    behind them; on about a third, drawers as well: a row of them under the top, above the
    doors, or a column of three at one end instead of a door."""
    width, depth, height = rng.uniform(0.8, 2.0), rng.uniform(0.58, 0.65), rng.uniform(0.88, 0.94)
    body, front, handle, stone = pick(rng, WOODS), pick(rng, WOODS + APPLIANCES), pick(rng, METALS), pick(rng, COUNTERTOPS)
    top_t = rng.uniform(0.03, 0.04)
    mass = float(rng.uniform(40, 100))
    layout = rng.random()
    hw, hd, kick, t = width / 2, depth / 2, 0.1, 0.018
    top_z = height - top_t
    yc = hd - 0.045  # the carcass front: the doors stand in front of it, behind the top's edge
    lo, hi = (-hw, -hd, top_z), (hw, hd, height)
    inner = shade(body, 0.9)
    columns = max(1, round(width / 0.45))
    parts = [block((-hw + 0.01, -hd, 0.0), (hw - 0.01, yc - 0.05, kick), shade(body, 0.5), "wood"),
             block((-hw, -hd, kick), (-hw + t, yc, top_z), body, "wood"),
             block((hw - t, -hd, kick), (hw, yc, top_z), body, "wood"),
             block((-hw + t, -hd, kick), (hw - t, -hd + t, top_z), inner, "wood"),
             block(lo, hi, stone, "ceramic")]
    moving, drawers = [], []
    door_pull, drawer_pull = _flat_pull(handle, 0.12, 0.02, vertical=True), _flat_pull(handle, 0.12, 0.02)
    slot_depth = depth - 0.05  # drawer boxes run back to the carcass's back
    # The door section (x0..x1), its doors' hinge sides and their top.
    x0, x1, door_top = -hw, hw, top_z
    if layout < 2 / 3:
        hinges = door_hinges(columns)
    elif layout < 2 / 3 + 2 / 9:  # a row of drawers under the top (one per column, at most three)
        door_top = top_z - rng.uniform(0.13, 0.17)
        n = columns if columns <= 3 else 2
        edges = np.linspace(-hw, hw, n + 1)
        for i in range(n):
            drawers.append(drawer(f"drawer_{i}", edges[i], edges[i + 1], yc + 0.02, slot_depth, door_top, top_z,
                                  front=front, body=inner, material="wood", handle=drawer_pull, side_clear=t + 0.008))
        hinges = door_hinges(columns)
    else:  # a column of three drawers at one end; the doors hinge away from it
        left = rng.random() < 0.5
        xe = -hw + width / columns if left else hw - width / columns
        bank = (-hw, xe) if left else (xe, hw)
        slots = np.linspace(kick, top_z, 4)
        for i in range(3):
            drawers.append(drawer(f"drawer_{i}", bank[0], bank[1], yc + 0.02, slot_depth, slots[i], slots[i + 1],
                                  front=front, body=inner, material="wood", handle=drawer_pull, side_clear=t + 0.008))
        parts.append(block((xe - t / 2, -hd + t, kick), (xe + t / 2, yc, top_z), inner, "wood"))
        x0, x1 = (xe + t / 2, hw) if left else (-hw, xe - t / 2)
        hinges = [not left] * min(2, columns - 1)
    # The carcass bottom and a shelf half way up, behind the doors.
    b0, b1 = max(x0, -hw + t), min(x1, hw - t)
    shelf_z = (kick + door_top) / 2
    floor_lo, floor_hi = (b0, -hd + t, kick), (b1, yc, kick + t)
    shelf_lo, shelf_hi = (b0, -hd + t, shelf_z), (b1, yc - 0.02, shelf_z + t)
    parts += [block(floor_lo, floor_hi, inner, "wood"), block(shelf_lo, shelf_hi, inner, "wood")]
    edges = np.linspace(-hw if x0 == -hw else x0 - t / 2, hw if x1 == hw else x1 + t / 2, len(hinges) + 1)
    for i, hinge_left in enumerate(hinges):
        moving.append(hinged_door(f"door_{i}", edges[i] + 0.002, edges[i + 1] - 0.002, yc + 0.02, kick + 0.003,
                                  door_top - 0.003, hinge_left=hinge_left, rgba=front, material="wood",
                                  handle=door_pull, handle_z=door_top - 0.09, handle_inset=0.04,
                                  hinge_at_front=True))
    recs = [top_receptacle("top", lo, hi),
            top_receptacle("shelf_0", floor_lo, floor_hi, clearance=shelf_z - floor_hi[2]),
            top_receptacle("shelf_1", shelf_lo, shelf_hi, clearance=door_top - shelf_hi[2])]
    moving += [link for link, _ in drawers]
    recs += [rec for _, rec in drawers]
    return finish("kitchen_counter", parts, moving=moving, receptacles=recs,
                  names=["countertop", "counter", "kitchen counter"], rooms=["kitchen"], placement="wall",
                  front_clearance=0.8, mass=mass)


def make_sink(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.6, 1.2), rng.uniform(0.5, 0.65), rng.uniform(0.82, 0.92)
    body, front, handle, stone = pick(rng, WOODS), pick(rng, WOODS + APPLIANCES), pick(rng, METALS), pick(rng, COUNTERTOPS)
    basin_c, basin_m = (pick(rng, METALS[:2]), "metal") if rng.random() < 0.5 else (WHITE, "ceramic")
    top_t, wall = rng.uniform(0.03, 0.04), 0.012
    hw, hd = width / 2, depth / 2
    bw = min(width - 0.16, rng.uniform(0.4, 0.6)) / 2
    front_strip = rng.uniform(0.06, 0.08)
    yb1 = hd - front_strip
    yb0 = max(-hd + 0.12, yb1 - rng.uniform(0.32, 0.42))
    floor = height - rng.uniform(0.15, 0.2)  # the basin's inner bottom
    parts = _base_cabinet(width, depth, height - top_t, 2, body, front, handle)
    # The countertop with a hole for the basin, as four strips around it.
    parts += [block((-hw, yb1, height - top_t), (hw, hd, height), stone, "ceramic"),
              block((-hw, -hd, height - top_t), (hw, yb0, height), stone, "ceramic"),
              block((-hw, yb0, height - top_t), (-bw, yb1, height), stone, "ceramic"),
              block((bw, yb0, height - top_t), (hw, yb1, height), stone, "ceramic")]
    floor_lo, floor_hi = (-bw, yb0, floor - wall), (bw, yb1, floor)
    parts += [block(floor_lo, floor_hi, basin_c, basin_m),
              block((-bw, yb0, floor), (-bw + wall, yb1, height - 0.003), basin_c, basin_m),
              block((bw - wall, yb0, floor), (bw, yb1, height - 0.003), basin_c, basin_m),
              block((-bw + wall, yb0, floor), (bw - wall, yb0 + wall, height - 0.003), basin_c, basin_m),
              block((-bw + wall, yb1 - wall, floor), (bw - wall, yb1, height - 0.003), basin_c, basin_m)]
    tap = pick(rng, METALS[:3])
    fy, fh = (yb0 - hd) / 2, rng.uniform(0.2, 0.3)  # middle of the back strip
    parts += [rod(0, fy, height, height + fh, 0.016, tap, "metal"),
              block((-0.012, fy, height + fh - 0.03), (0.012, yb0 + 0.1, height + fh), tap, "metal")]
    recs = [top_receptacle("basin", (-bw + wall, yb0 + wall, 0.0), (bw - wall, yb1 - wall, floor),
                           clearance=height - floor)]
    if hw - bw >= 0.16:
        recs += [top_receptacle("counter_left", (-hw, -hd, 0.0), (-bw, hd, height)),
                 top_receptacle("counter_right", (bw, -hd, 0.0), (hw, hd, height))]
    return finish("sink", parts, receptacles=recs, names=["sink", "washbasin", "basin"],
                  rooms=["kitchen", "bathroom"], placement="wall", front_clearance=0.7,
                  mass=float(rng.uniform(30, 70)))


def make_fridge(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.6, 0.9), rng.uniform(0.62, 0.75), rng.uniform(1.5, 1.9)
    shell, handle = pick(rng, APPLIANCES, jitter=0.02), pick(rng, METALS[:4])
    liner = (0.93, 0.94, 0.95, 1.0)
    t, door_t, base = 0.04, rng.uniform(0.05, 0.07), rng.uniform(0.03, 0.08)
    hw, hd = width / 2, depth / 2
    yf = hd - door_t
    split = height - rng.uniform(0.4, 0.55) if rng.random() < 0.6 else None  # a top freezer
    ceiling = (split if split is not None else height) - t
    bottom_lo, bottom_hi = (-hw + t, -hd + t, 0.0), (hw - t, yf, base + t)
    parts = [
        block((-hw, -hd, 0.0), (-hw + t, yf, height), shell, "metal"),
        block((hw - t, -hd, 0.0), (hw, yf, height), shell, "metal"),
        block((-hw + t, -hd, height - t), (hw - t, yf, height), shell, "metal"),
        block((-hw + t, -hd, 0.0), (hw - t, -hd + t, height - t), shell, "metal"),
        block(bottom_lo, bottom_hi, liner, "plastic"),
    ]
    recs = []
    levels = np.linspace(bottom_hi[2], ceiling, 4)
    shelves = [(bottom_lo, bottom_hi)]
    for z in levels[1:-1]:
        lo, hi = (-hw + t, -hd + t, z - 0.01), (hw - t, yf - 0.06, z + 0.01)
        parts.append(block(lo, hi, liner, "glass"))
        shelves.append((lo, hi))
    for i, (lo, hi) in enumerate(shelves):
        above = shelves[i + 1][0][2] if i + 1 < len(shelves) else ceiling
        recs.append(top_receptacle(f"shelf_{i}", lo, hi, clearance=float(above - hi[2])))
    hinge_left = rng.random() < 0.5
    moving = []
    if split is not None:
        parts.append(block((-hw + t, -hd + t, split - t), (hw - t, yf, split), shell, "metal"))
        moving.append(hinged_door("door_1", -hw, hw, yf, split + 0.003, height, hinge_left=hinge_left,
                                  rgba=shell, material="metal", handle=_door_bar(handle), thickness=door_t))
        main_top = split - 0.003
    else:
        main_top = height
    moving.insert(0, hinged_door("door_0", -hw, hw, yf, base, main_top, hinge_left=hinge_left, rgba=shell,
                                 material="metal", handle=_door_bar(handle), thickness=door_t,
                                 handle_z=min(1.1, main_top - 0.25)))
    return finish("fridge", parts, moving=moving, receptacles=recs, names=["fridge", "refrigerator"],
                  rooms=["kitchen"], placement="wall", front_clearance=max(0.8, width + 0.1),
                  mass=float(rng.uniform(50, 90)))


def make_toilet(rng: np.random.Generator) -> AssetModel:
    width, seat_h = rng.uniform(0.36, 0.42), rng.uniform(0.39, 0.43)
    porcelain = pick(rng, ((0.96, 0.96, 0.95), (0.93, 0.92, 0.88)), jitter=0.02)
    seat_c, seat_m = (porcelain, "plastic") if rng.random() < 0.7 else (pick(rng, WOODS), "wood")
    tank_d, tank_top = rng.uniform(0.17, 0.22), rng.uniform(0.72, 0.82)
    r = width / 2
    oval = rng.uniform(1.25, 1.4)  # the bowl is longer (y) than wide
    bowl_y = -0.35 + tank_d + r * oval * 0.75
    parts = [
        lathe([(r * 0.55, 0.0), (r * 0.5, 0.12), (r * 0.92, seat_h - 0.06), (r * 0.97, seat_h - 0.03)],
              porcelain, "ceramic", center=(0, bowl_y, 0), scale_xy=(1.0, oval)),
        lathe([(r, seat_h - 0.03), (r, seat_h)], seat_c, seat_m, center=(0, bowl_y, 0), scale_xy=(1.0, oval)),
        block((-r, -0.35, 0.36), (r, -0.35 + tank_d, tank_top - 0.02), porcelain, "ceramic"),
    ]
    lid_lo, lid_hi = (-r - 0.01, -0.35 - 0.005, tank_top - 0.02), (r + 0.01, -0.35 + tank_d + 0.01, tank_top)
    parts += [block(lid_lo, lid_hi, porcelain, "ceramic"),
              block((-0.1, -0.35, 0.3), (0.1, -0.35 + 0.06, 0.36), porcelain, "ceramic"),
              block((-r + 0.02, -0.35 + tank_d, tank_top - 0.07), (-r + 0.08, -0.35 + tank_d + 0.012, tank_top - 0.05),
                    pick(rng, METALS[:2]), "metal", collision="none")]
    return finish("toilet", parts, receptacles=[top_receptacle("tank", lid_lo, lid_hi, inset=0.02)],
                  names=["toilet", "toilet bowl"], rooms=["bathroom"], placement="wall",
                  front_clearance=0.6, mass=float(rng.uniform(25, 45)))


def make_bathtub(rng: np.random.Generator) -> AssetModel:
    length, width, height = rng.uniform(1.5, 1.8), rng.uniform(0.7, 0.8), rng.uniform(0.5, 0.6)
    enamel = pick(rng, ((0.96, 0.96, 0.95), (0.93, 0.92, 0.88), (0.9, 0.92, 0.93)), jitter=0.02)
    wall, bottom = rng.uniform(0.06, 0.1), rng.uniform(0.06, 0.1)
    hl, hw = length / 2, width / 2
    floor_lo, floor_hi = (-hl, -hw, 0.0), (hl, hw, bottom)
    parts = [
        block(floor_lo, floor_hi, enamel, "ceramic"),
        block((-hl, -hw, bottom), (-hl + wall, hw, height), enamel, "ceramic"),
        block((hl - wall, -hw, bottom), (hl, hw, height), enamel, "ceramic"),
        block((-hl + wall, -hw, bottom), (hl - wall, -hw + wall, height), enamel, "ceramic"),
        block((-hl + wall, hw - wall, bottom), (hl - wall, hw, height), enamel, "ceramic"),
    ]
    tap = pick(rng, METALS[:3])
    tx = -hl + wall / 2  # on the end wall, the spout reaching over the tub
    parts += [rod(tx, 0.0, height, height + 0.12, 0.015, tap, "metal"),
              block((tx - 0.012, -0.012, height + 0.1), (tx + 0.15, 0.012, height + 0.12), tap, "metal")]
    inner = top_receptacle("tub", (-hl + wall, -hw + wall, 0.0), (hl - wall, hw - wall, bottom),
                           clearance=height - bottom)
    return finish("bathtub", parts, receptacles=[inner], names=["bathtub", "tub", "bath"],
                  rooms=["bathroom"], placement="wall", front_clearance=0.6,
                  mass=float(rng.uniform(40, 120)))


FACTORIES = {
    "bed": make_bed,
    "sofa": make_sofa,
    "armchair": make_armchair,
    "dining_table": make_dining_table,
    "coffee_table": make_coffee_table,
    "desk": make_desk,
    "chair": make_chair,
    "bookshelf": make_bookshelf,
    "wardrobe": make_wardrobe,
    "dresser": make_dresser,
    "nightstand": make_nightstand,
    "fridge": make_fridge,
    "kitchen_counter": make_kitchen_counter,
    "sink": make_sink,
    "toilet": make_toilet,
    "bathtub": make_bathtub,
    "tv_stand": make_tv_stand,
    "tv": make_tv,
    "plant": make_plant,
    "side_table": make_side_table,
    "floor_lamp": make_floor_lamp,
}

register_builtins(FACTORIES)
