"""Built-in kitchen and laundry appliances and kitchen furniture (parametric, seeded, low-poly; registered on import).

Cooking: stove (range with cooktop and oven), microwave (side-hinged door), coffee machine,
toaster. Cleaning: dishwasher, washing machine, dryer, trash can. Kitchen furniture: kitchen
island, bar stool, pantry cabinet (hinged doors, shelves inside).

The conventions are those of :mod:`legent_gym.world.assets.library.furniture`: z up, the
footprint centred on the origin, the front facing +y; doors hinge about a vertical front
edge and swing toward +y; surfaces that hold things are solid tops whose upper face is
exactly the receptacle height.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from legent_gym.world.assets.library.common import (
    APPLIANCES,
    BRIGHT_PLASTICS,
    CERAMICS,
    COUNTERTOPS,
    DARK_PLASTICS,
    DOOR_RANGE,
    FABRICS,
    GLASSES,
    LEATHERS,
    METALS,
    RGBA,
    SCREEN,
    WOODS,
    Handle,
    annulus,
    block,
    finish,
    hinged_door,
    lathe,
    pick,
    register_builtins,
    rod,
    round_top,
    shade,
    top_receptacle,
    transformed,
)
from legent_gym.world.assets.model import AssetModel, Collision, Joint, Link, Part, Receptacle

KITCHEN = ["kitchen"]
LAUNDRY = ["bathroom", "kitchen"]
#: Tinted glass of oven and microwave windows: dark enough to read as glass over any shell.
OVEN_GLASS: RGBA = (0.12, 0.13, 0.15, 1.0)
#: Painted kitchen cabinet fronts besides wood: white, cream, grey, sage, navy.
CABINET_PAINTS = ((0.93, 0.93, 0.91), (0.88, 0.85, 0.77), (0.55, 0.57, 0.58), (0.55, 0.62, 0.52), (0.2, 0.26, 0.38))

Span = Callable[[float, float], tuple[float, float]]


# ---------------------------------------------------------------------------------------
# Shared pieces.


def _span(hinge_left: bool) -> Span:
    """Maps distances (u0, u1) from a door's hinge edge to the sorted x range in the door
    link's frame: a left-hinged door lies on x >= 0, a right-hinged one on x <= 0."""
    if hinge_left:
        return lambda u0, u1: (u0, u1)
    return lambda u0, u1: (-u1, -u0)


def _door_block(span: Span, u0: float, u1: float, y0: float, y1: float, z0: float, z1: float, rgba: RGBA,
                material: str, collision: Collision = "box") -> Part:
    x0, x1 = span(u0, u1)
    return block((x0, y0, z0), (x1, y1, z1), rgba, material, collision=collision)


def _cabinet_pull(style: str, rgba: RGBA) -> Handle:
    """A cabinet door's handle: "bar" (a vertical pull, 30 % of the door's height and at most
    35 cm long) or "knob"."""
    def make(x: float, y: float, z: float, height: float) -> list[Part]:
        if style == "bar":
            hl = min(0.35, 0.3 * height)
            return [block((x - 0.011, y, z - hl / 2), (x + 0.011, y + 0.03, z + hl / 2), rgba, "metal")]
        return [block((x - 0.015, y, z - 0.015), (x + 0.015, y + 0.028, z + 0.015), rgba, "metal")]
    return make


def _facing_front(part: Part, x: float, y: float, z: float) -> Part:
    """A part built about the z axis (a knob, a porthole), turned so that its axis points
    +y and its base (z = 0) lies on the plane y at (x, z)."""
    return transformed(part, rotate_x=-np.pi / 2, offset=(x, y, z))


def _knob(x: float, y: float, z: float, radius: float, depth: float, rgba: RGBA, *, segments: int = 8,
          material: str = "plastic") -> Part:
    """A round knob or dial on a front face at y, sticking out toward +y (decorative)."""
    part = rod(0.0, 0.0, 0.0, depth, radius, rgba, material, segments=segments, collision="none")
    return _facing_front(part, x, y, z)


def _slanted(part: Part, dx: float, dy: float) -> Part:
    """``part`` sheared so that its top moves by (dx, dy) while its bottom stays (a splayed
    leg): a shear keeps the volume and the faces' orientation."""
    v = part.vertices.copy()
    z0, z1 = v[:, 2].min(), v[:, 2].max()
    f = (v[:, 2] - z0) / (z1 - z0)
    v[:, 0] += f * dx
    v[:, 1] += f * dy
    return Part.exact(v, part.faces.copy(), part.rgba, part.collision, material=part.material)


def _buttons(x0: float, x1: float, y: float, z: float, n: int, size: float, rgba: RGBA) -> list[Part]:
    """``n`` square push buttons in a row from x0 to x1 on the front face at y (decorative)."""
    xs = np.linspace(x0 + size, x1 - size, n) if n > 1 else [(x0 + x1) / 2]
    return [block((x - size / 2, y, z - size / 2), (x + size / 2, y + 0.006, z + size / 2), rgba, "plastic",
                  collision="none") for x in xs]


def _trim(shell: RGBA) -> RGBA:
    """Control-panel and trim colour that reads against a shell: near-black on light
    shells, charcoal on black ones."""
    return (0.1, 0.1, 0.11, 1.0) if sum(shell[:3]) > 1.0 else (0.3, 0.3, 0.32, 1.0)


# ---------------------------------------------------------------------------------------
# Cooking.


def make_stove(rng: np.random.Generator) -> AssetModel:
    width, depth = rng.uniform(0.5, 0.9), rng.uniform(0.6, 0.68)
    top_z = rng.uniform(0.88, 0.92)  # the cooktop
    shell, handle_c = pick(rng, APPLIANCES, jitter=0.02), pick(rng, METALS[:4])
    trim = _trim(shell)
    gas = rng.random() < 0.55
    knobs_back = rng.random() < 0.4  # on a raised backguard (North American) or on the front strip
    door_t, plate_t = rng.uniform(0.04, 0.06), 0.015
    hw, hd = width / 2, depth / 2
    yf = hd - door_t
    drawer = rng.random() < 0.6  # a storage drawer under the oven, else a recessed toe kick
    kick = rng.uniform(0.12, 0.17) if drawer else rng.uniform(0.06, 0.1)
    panel_h = 0.0 if knobs_back else rng.uniform(0.07, 0.11)
    door_top = top_z - plate_t - panel_h - 0.005
    parts = [block((-hw, -hd, 0.0 if drawer else kick), (hw, yf, top_z - plate_t), shell, "metal")]
    if drawer:
        parts.append(block((-hw, yf, 0.01), (hw, hd, kick - 0.004), shell, "metal"))
    else:
        parts.append(block((-hw + 0.01, -hd, 0.0), (hw - 0.01, yf - 0.05, kick), trim, "metal"))
    parts += [block((-hw, yf, kick), (hw, hd, door_top), shell, "metal"),
              block((-hw + 0.08, hd, kick + 0.1), (hw - 0.08, hd + 0.003, door_top - 0.09), OVEN_GLASS, "glass",
                    collision="none")]
    hz = door_top - 0.045
    if rng.random() < 0.6:  # a bar on two standoffs across the top of the door
        parts += [block((-hw + 0.05, hd + 0.03, hz - 0.011), (hw - 0.05, hd + 0.05, hz + 0.011), handle_c, "metal"),
                  *[block((x - 0.012, hd, hz - 0.01), (x + 0.012, hd + 0.03, hz + 0.01), handle_c, "metal")
                    for x in (-hw + 0.07, hw - 0.07)]]
    else:  # a full-width pull lip
        parts.append(block((-hw + 0.03, hd, hz - 0.012), (hw - 0.03, hd + 0.025, hz + 0.012), handle_c, "metal"))

    # The cooktop: a plate over the body; behind it, a backguard with the knobs or a low upstand.
    back = -hd
    if knobs_back:
        bg_t, bg_h = rng.uniform(0.04, 0.07), rng.uniform(0.1, 0.18)
        parts.append(block((-hw, -hd, top_z - plate_t), (hw, -hd + bg_t, top_z + bg_h), shell, "metal"))
        back, knob_y, knob_z = -hd + bg_t, -hd + bg_t, top_z + bg_h / 2
    else:
        parts.append(block((-hw, yf, door_top + 0.005), (hw, hd, top_z - plate_t), trim, "metal"))
        knob_y, knob_z = hd, door_top + 0.005 + panel_h / 2
        if rng.random() < 0.5:
            up_t = 0.02
            parts.append(block((-hw, -hd, top_z - plate_t), (hw, -hd + up_t, top_z + rng.uniform(0.04, 0.08)),
                               shell, "metal"))
            back = -hd + up_t
    plate_c = (pick(rng, METALS[:1] + METALS[2:4], jitter=0.02) if gas else (0.05, 0.05, 0.06, 1.0))
    plate_lo, plate_hi = (-hw, back, top_z - plate_t), (hw, hd, top_z)
    parts.append(block(plate_lo, plate_hi, plate_c, "metal" if gas else "glass"))

    if width < 0.55:
        burners = 2 if rng.random() < 0.4 else 4
    elif width < 0.8:
        burners = 4 if rng.random() < 0.8 else 3
    else:
        burners = 5 if rng.random() < 0.6 else 4
    # The cooking field: cells left/right and front/back of its middle lines.
    margin = rng.uniform(0.03, 0.05)
    y0, y1 = back + margin, hd - rng.uniform(0.05, 0.08)
    ym, xw = (y0 + y1) / 2, hw - margin
    cx, cyb, cyf = xw / 2, (y0 + ym) / 2, (ym + y1) / 2
    spots = {2: [(-cx, cyf), (cx, cyb)], 3: [(-cx, cyb), (-cx, cyf), (cx, ym)],
             4: [(-cx, cyb), (-cx, cyf), (cx, cyb), (cx, cyf)],
             5: [(-cx, cyb), (-cx, cyf), (cx, cyb), (cx, cyf), (0.0, ym)]}[burners]
    cell = min(cx, (y1 - y0) / 4)
    if gas:
        burner_c, grate_c = pick(rng, METALS[2:4], jitter=0.02), (0.08, 0.08, 0.09, 1.0)
        for x, y in spots:
            r = cell * rng.uniform(0.35, 0.55)
            parts.append(rod(x, y, top_z, top_z + 0.02, r, burner_c, "metal", segments=6, collision="none"))
        # Cast-iron grates: bars along the field's edges and middle lines, all level, so a pot
        # stands on them and the receptacle's corners and centre lie on a bar.
        gh, b = rng.uniform(0.025, 0.035), 0.0125
        g = top_z + gh
        parts += [block((-xw - b, y - b, top_z), (xw + b, y + b, g), grate_c, "metal") for y in (y0, ym, y1)]
        parts += [block((x - b, y0 + b, top_z), (x + b, y1 - b, g), grate_c, "metal") for x in (-xw, 0.0, xw)]
        cooktop = Receptacle("cooktop", (0.0, ym), (xw, (y1 - y0) / 2), g, clearance=0.6)
    else:
        ring_c = pick(rng, ((0.45, 0.45, 0.47), (0.55, 0.2, 0.15), (0.7, 0.7, 0.72)), jitter=0.03)
        for x, y in spots:
            r = cell * rng.uniform(0.6, 0.85)
            parts.append(rod(x, y, top_z, top_z + 0.0015, r, ring_c, "glass", segments=8, collision="none"))
        cooktop = top_receptacle("cooktop", (-hw, back, 0.0), (hw, hd, top_z), inset=0.04, clearance=0.6)

    knobs = burners + 1
    kx = hw - 0.06
    knob_c = pick(rng, METALS[:4], jitter=0.02)
    ks = rng.uniform(0.032, 0.042)  # knob size
    for x in np.linspace(-kx, kx, knobs):
        parts.append(block((x - ks / 2, knob_y, knob_z - ks / 2), (x + ks / 2, knob_y + 0.025, knob_z + ks / 2),
                           knob_c, "plastic", collision="none"))
    return finish("stove", parts, receptacles=[cooktop], names=["stove", "cooker", "range", "oven"],
                  rooms=KITCHEN, placement="wall", front_clearance=0.9,
                  mass=float(40 + 50 * (width - 0.5) + rng.uniform(0, 15)))


def make_microwave(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.44, 0.6), rng.uniform(0.32, 0.42), rng.uniform(0.25, 0.34)
    shell = pick(rng, APPLIANCES, jitter=0.02)
    front = shell if rng.random() < 0.5 else pick(rng, ((0.1, 0.1, 0.11), (0.76, 0.77, 0.78)), jitter=0.02)
    door_t, wall, floor_t = rng.uniform(0.03, 0.045), 0.02, rng.uniform(0.025, 0.04)
    panel_w = rng.uniform(0.1, 0.14)
    hw, hd = width / 2, depth / 2
    yf = hd - door_t
    # Seen from the front (+y), -x is on the right: the control panel there, the hinge on +x.
    xp = -hw + panel_w  # the control panel's inner edge (the cavity's right wall)
    ceiling = height - wall
    parts = [
        block((-hw, -hd, 0.0), (hw, yf, floor_t), shell, "metal"),
        block((-hw, -hd, ceiling), (hw, yf, height), shell, "metal"),
        block((hw - wall, -hd, floor_t), (hw, yf, ceiling), shell, "metal"),
        block((xp, -hd, floor_t), (hw - wall, -hd + wall, ceiling), shell, "metal"),
        block((-hw, -hd, floor_t), (xp, yf, ceiling), shell, "metal"),
        block((-hw, yf, 0.0), (xp - 0.003, hd, height), front, "metal"),
    ]
    # The control panel: a display, a keypad or a dial, and the door release.
    px0, px1 = -hw + 0.02, xp - 0.02
    disp_top = height - rng.uniform(0.03, 0.05)
    parts.append(block((px0, hd, disp_top - 0.035), (px1, hd + 0.003, disp_top), SCREEN, "glass", collision="none"))
    keys = pick(rng, DARK_PLASTICS, jitter=0.02)
    if rng.random() < 0.5:
        r = min(0.035, (px1 - px0) / 2 - 0.005)
        parts.append(_knob((px0 + px1) / 2, hd, disp_top - 0.08, r, 0.02, keys, segments=10))
    else:
        parts.append(block((px0, hd, height * 0.35), (px1, hd + 0.004, disp_top - 0.05), shade(front, 0.8),
                           "plastic", collision="none"))
    parts.append(block((px0, hd, 0.03), (px1, hd + 0.008, 0.06), keys, "plastic", collision="none"))

    # The turntable on the cavity floor holds things.
    cx0, cx1, cy0, cy1 = xp, hw - wall, -hd + wall, yf
    tcx, tcy = (cx0 + cx1) / 2, (cy0 + cy1) / 2
    tr = min(cx1 - cx0, cy1 - cy0) / 2 - 0.015
    plate_top, seg = floor_t + 0.008, 12
    parts.append(rod(tcx, tcy, floor_t, plate_top, tr, (0.82, 0.86, 0.86, 1.0), "glass", segments=seg))
    turntable = round_top("turntable", tr, seg, plate_top, inset=0.01, center=(tcx, tcy),
                          clearance=ceiling - plate_top)

    # The door, hinged at x = hw (turning about -z), a window, and a pull at its free edge. Not
    # hinged_door, whose handle is placed from the free edge: the window and pull are measured from the hinge.
    dw = hw - xp
    span = _span(False)
    door = [_door_block(span, 0.0, dw, 0.0, door_t, 0.004, height - 0.004, front, "metal")]
    grip = rng.random() < 0.5
    door.append(_door_block(span, 0.04, dw - (0.07 if grip else 0.05), door_t, door_t + 0.002, 0.05, height - 0.05,
                            OVEN_GLASS, "glass", "none"))
    if grip:  # a vertical bar handle
        door.append(_door_block(span, dw - 0.04, dw - 0.02, door_t, door_t + 0.03, 0.05, height - 0.05,
                                pick(rng, METALS[:4]), "metal"))
    moving = [Link("door_0", door, (hw, yf, 0.0), Joint("hinge", (0.0, 0.0, -1.0), DOOR_RANGE))]
    return finish("microwave", parts, moving=moving, receptacles=[turntable],
                  names=["microwave", "microwave oven"], rooms=KITCHEN, placement="surface",
                  front_clearance=0.4, mass=float(10 + 20 * (width - 0.44) + rng.uniform(0, 4)))


def make_coffee_machine(rng: np.random.Generator) -> AssetModel:
    shell = pick(rng, DARK_PLASTICS + METALS[:2] + BRIGHT_PLASTICS[:2], jitter=0.03)
    accent = pick(rng, METALS[:3], jitter=0.02)
    tank_c = pick(rng, GLASSES[:1] + ((0.55, 0.6, 0.65),), jitter=0.03)
    style = ("espresso", "drip", "pod")[int(rng.integers(3))]
    if style == "pod":
        width, depth, height = rng.uniform(0.14, 0.2), rng.uniform(0.28, 0.38), rng.uniform(0.25, 0.32)
    else:
        width, depth, height = rng.uniform(0.2, 0.34), rng.uniform(0.25, 0.4), rng.uniform(0.3, 0.42)
    hw, hd = width / 2, depth / 2
    base_h = rng.uniform(0.03, 0.05)
    tower = -hd + depth * rng.uniform(0.45, 0.55)  # front face of the back tower
    head_z = height - rng.uniform(0.07, 0.1)  # underside of the head that overhangs the front
    tank_d = min(0.1, (tower + hd) * 0.45)
    parts = [
        block((-hw, -hd, 0.0), (hw, hd, base_h), shell, "plastic"),
        block((-hw, -hd + tank_d, base_h), (hw, tower, height), shell, "plastic"),
        block((-hw, tower, head_z), (hw, hd - 0.01, height), shell, "plastic"),
        # The water tank at the back, behind the tower.
        block((-hw + 0.01, -hd, base_h), (hw - 0.01, -hd + tank_d, height - 0.02), tank_c, "glass"),
    ]
    if style == "drip":
        # A hot plate and a glass carafe under the filter head.
        cr = min(hw - 0.02, (hd - tower) / 2 - 0.005, 0.075)
        cy = (tower + hd) / 2
        ch = min(head_z - base_h - 0.02, rng.uniform(0.13, 0.18))
        parts += [rod(0, cy, base_h, base_h + 0.008, cr + 0.01, accent, "metal", segments=10),
                  lathe([(cr * 0.95, base_h + 0.008), (cr, base_h + ch * 0.5), (cr * 0.6, base_h + ch * 0.85),
                         (cr * 0.65, base_h + ch)], GLASSES[0] + (1.0,), "glass", segments=10,
                        center=(0.0, cy, 0.0)),
                  block((cr * 0.6, cy - 0.012, base_h + ch * 0.35), (cr + 0.03, cy + 0.012, base_h + ch * 0.85),
                        shade(shell, 0.7), "plastic", collision="none"),
                  rod(0, cy, head_z - 0.03, head_z, min(cr, 0.06), shade(shell, 0.85), "plastic", segments=10)]
        parts += _buttons(-hw + 0.02, hw - 0.02, hd, base_h / 2, 3, 0.012, accent)
        names = ["coffee machine", "coffee maker", "drip coffee maker"]
    else:
        # A drip tray with a grille, a spout or group head under the head, and controls on top.
        tray_h = rng.uniform(0.02, 0.03)
        parts += [block((-hw + 0.015, tower, base_h), (hw - 0.015, hd, base_h + tray_h), accent, "metal"),
                  block((-hw + 0.03, tower + 0.01, base_h + tray_h), (hw - 0.03, hd - 0.015, base_h + tray_h + 0.003),
                        shade(accent, 0.6), "metal", collision="none")]
        sy = (tower + hd) / 2
        if style == "espresso":
            parts += [rod(0, sy, head_z - 0.03, head_z, 0.035, accent, "metal", segments=10),
                      block((-0.012, sy, head_z - 0.045), (0.012, hd + 0.08, head_z - 0.025), (0.1, 0.1, 0.1, 1.0),
                            "plastic", collision="none"),
                      rod(hw - 0.025, hd - 0.03, head_z - 0.12, head_z, 0.005, accent, "metal", segments=6,
                          collision="none")]
            names = ["coffee machine", "espresso machine", "coffee maker"]
            if rng.random() < 0.5:  # a bean hopper on top
                parts.append(rod(0, (-hd + tank_d + tower) / 2, height, height + 0.05, min(hw - 0.02, 0.06),
                                 (0.25, 0.18, 0.12, 1.0), "plastic", segments=8, radius_top=min(hw - 0.01, 0.07)))
        else:
            parts.append(rod(0, sy, head_z - 0.015, head_z, 0.02, accent, "plastic", segments=8))
            names = ["coffee machine", "coffee maker", "pod machine", "capsule machine"]
        parts += _buttons(-hw + 0.02, hw - 0.02, hd - 0.01, height - 0.03, 2 if style == "pod" else 3, 0.014,
                          accent)
        parts.append(block((-hw + 0.02, hd - 0.01, head_z + 0.008), (hw - 0.02, hd - 0.006, head_z + 0.025),
                           SCREEN, "glass", collision="none"))
    return finish("coffee_machine", parts, names=names, rooms=KITCHEN, placement="surface",
                  front_clearance=0.3, mass=float(rng.uniform(3, 10) * width / 0.3))


def make_toaster(rng: np.random.Generator) -> AssetModel:
    slots = 2 if rng.random() < 0.55 else 4
    long4 = slots == 4 and rng.random() < 0.5  # two pairs end to end, with a lever at each end
    width = rng.uniform(0.38, 0.46) if long4 else rng.uniform(0.25, 0.32)
    depth = rng.uniform(0.26, 0.3) if slots == 4 and not long4 else rng.uniform(0.15, 0.2)
    height = rng.uniform(0.17, 0.22)
    body_c, body_m = ((pick(rng, METALS[:2], jitter=0.02), "metal") if rng.random() < 0.5
                      else (pick(rng, CERAMICS + BRIGHT_PLASTICS[:3] + DARK_PLASTICS[:1]), "plastic"))
    base_c = pick(rng, DARK_PLASTICS[:2], jitter=0.02)
    hw, hd, base_h = width / 2, depth / 2, rng.uniform(0.015, 0.025)
    parts = [block((-hw + 0.01, -hd + 0.01, 0.0), (hw - 0.01, hd - 0.01, base_h), base_c, "plastic")]
    rounded = rng.random() < 0.5
    if rounded:  # an elliptic prism with a softened top edge
        seg = 14
        k = 1.0 / np.cos(np.pi / seg)
        parts.append(lathe([(k, base_h), (k, height - 0.015), (k * 0.93, height)], body_c, body_m, segments=seg,
                           scale_xy=(hw, hd)))
        inner_x, inner_y = hw * 0.72, hd * 0.65
    else:
        parts.append(block((-hw, -hd, base_h), (hw, hd, height), body_c, body_m))
        inner_x, inner_y = hw - 0.03, hd - 0.03
    slot_w, slot_c = rng.uniform(0.028, 0.036), (0.05, 0.05, 0.05, 1.0)
    if slots == 4 and not long4:
        ys = np.linspace(-inner_y + slot_w / 2, inner_y - slot_w / 2, 4)
        runs = [(-inner_x, inner_x)]
    else:
        ys = np.linspace(-inner_y * 0.6, inner_y * 0.6, 2)
        runs = [(-inner_x, -0.01), (0.01, inner_x)] if long4 else [(-inner_x, inner_x)]
    for x0, x1 in runs:
        for y in ys:
            parts.append(block((x0, y - slot_w / 2, height - 0.004), (x1, y + slot_w / 2, height + 0.001), slot_c,
                               "plastic", collision="none"))
    # Levers on the ends (both for a long four-slot), and a browning knob on the front.
    lever_c = pick(rng, DARK_PLASTICS[:3] + METALS[1:2], jitter=0.02)
    lz = height * rng.uniform(0.55, 0.7)
    for sign in ((-1, 1) if long4 else (1,)):
        x0, x1 = sorted((sign * (hw - 0.002), sign * (hw + 0.022)))
        parts.append(block((x0, -0.012, lz - 0.01), (x1, 0.012, lz + 0.01), lever_c, "plastic", collision="none"))
    # The front of a rounded body is flat only near x = 0.
    kx = -hw + 0.05 if not (long4 or rounded) else 0.0
    parts.append(_knob(kx, hd, base_h + 0.04, 0.013, 0.015, lever_c))
    return finish("toaster", parts, names=["toaster", "bread toaster"], rooms=KITCHEN, placement="surface",
                  front_clearance=0.2, mass=float(rng.uniform(1.0, 1.6) + (0.8 if slots == 4 else 0.0)))


# ---------------------------------------------------------------------------------------
# Cleaning and laundry.


def make_dishwasher(rng: np.random.Generator) -> AssetModel:
    width = rng.uniform(0.44, 0.46) if rng.random() < 0.25 else rng.uniform(0.595, 0.605)
    depth, height = rng.uniform(0.55, 0.62), rng.uniform(0.82, 0.87)
    shell = pick(rng, APPLIANCES, jitter=0.02)
    trim = _trim(shell)
    top_c = shell if rng.random() < 0.6 else pick(rng, WOODS[:5] + COUNTERTOPS)
    door_t, top_t, kick = rng.uniform(0.04, 0.06), rng.uniform(0.02, 0.035), rng.uniform(0.07, 0.11)
    hw, hd = width / 2, depth / 2
    yf = hd - door_t
    top_z = height - top_t
    panel_h = rng.uniform(0.06, 0.1)
    panel_dark = rng.random() < 0.5
    top_lo, top_hi = (-hw, -hd, top_z), (hw, hd, height)
    parts = [
        block((-hw, -hd, kick), (hw, yf, top_z), shell, "metal"),
        block((-hw + 0.01, -hd, 0.0), (hw - 0.01, yf - 0.03, kick), trim, "metal"),
        block(top_lo, top_hi, top_c, "wood" if top_c != shell else "metal"),
        block((-hw + 0.003, yf, kick + 0.003), (hw - 0.003, hd, top_z - panel_h), shell, "metal"),
        block((-hw + 0.003, yf, top_z - panel_h), (hw - 0.003, hd, top_z - 0.002),
              trim if panel_dark else shade(shell, 0.93), "metal"),
    ]
    pz = top_z - panel_h / 2
    keys = (0.85, 0.85, 0.86, 1.0) if panel_dark else pick(rng, DARK_PLASTICS[:2], jitter=0.02)
    n = int(rng.integers(3, 7))
    parts += _buttons(-hw + 0.05, hw * 0.2, hd, pz, n, 0.014, keys)
    if rng.random() < 0.5:
        parts.append(_knob(hw - 0.09, hd, pz, min(0.028, panel_h / 2 - 0.008), 0.02, keys, segments=10))
    else:
        parts.append(block((hw * 0.35, hd, pz - 0.015), (hw - 0.04, hd + 0.003, pz + 0.015), SCREEN, "glass",
                           collision="none"))
    handle_c = pick(rng, METALS[:4], jitter=0.02)
    hz = top_z - panel_h - 0.05
    if rng.random() < 0.55:  # a bar across the door on two standoffs
        parts += [block((-hw + 0.08, hd + 0.025, hz - 0.01), (hw - 0.08, hd + 0.045, hz + 0.01), handle_c, "metal"),
                  *[block((x - 0.01, hd, hz - 0.008), (x + 0.01, hd + 0.025, hz + 0.008), handle_c, "metal")
                    for x in (-hw + 0.1, hw - 0.1)]]
    else:  # a pocket grip under the panel
        parts.append(block((-0.09, hd, hz - 0.012), (0.09, hd + 0.004, hz + 0.012), (0.08, 0.08, 0.09, 1.0),
                           "plastic", collision="none"))
    return finish("dishwasher", parts, receptacles=[top_receptacle("top", top_lo, top_hi)],
                  names=["dishwasher", "dish washer", "dishwashing machine"], rooms=KITCHEN, placement="wall",
                  front_clearance=0.9, mass=float(rng.uniform(35, 55) * width / 0.6))


def _porthole(x: float, y: float, z: float, r_out: float, r_in: float, depth: float, rim: RGBA,
              window: RGBA, *, bulge: float, opaque: bool) -> list[Part]:
    """A round front-loader door on the front plane y: a rim ring and a window (a domed
    glass bowl, or a flat opaque disc)."""
    ring = _facing_front(annulus((r_out, r_out), (r_in, r_in), 0.0, depth, rim, "plastic", segments=12), x, y, z)
    if opaque:
        pane = rod(0.0, 0.0, 0.0, depth - 0.004, r_in + 0.002, window, "plastic", segments=12, collision="none")
    else:
        pane = lathe([(r_in + 0.002, 0.0), (r_in * 0.85, depth + bulge * 0.6), (0.0, depth + bulge)], window, "glass",
                     segments=12, collision="none")
    return [ring, _facing_front(pane, x, y, z)]


def _laundry_shell(rng: np.random.Generator, width: float, depth: float, height: float, shell: RGBA,
                   panel_c: RGBA) -> tuple[list[Part], Receptacle, float, float]:
    """Body, feet plinth, top and control strip of a front loader. Returns the parts, the
    top receptacle, the body's front plane (the strip stands 6 mm proud of it) and the
    strip's lower edge."""
    hw, hd = width / 2, depth / 2
    top_t, kick = rng.uniform(0.015, 0.025), rng.uniform(0.02, 0.05)
    top_z = height - top_t
    panel_h = rng.uniform(0.1, 0.14)
    top_lo, top_hi = (-hw, -hd, top_z), (hw, hd, height)
    parts = [
        block((-hw, -hd, kick), (hw, hd, top_z), shell, "metal"),
        block((-hw + 0.03, -hd + 0.03, 0.0), (hw - 0.03, hd - 0.04, kick), (0.15, 0.15, 0.16, 1.0), "plastic"),
        block(top_lo, top_hi, shell, "metal"),
        block((-hw + 0.003, hd, top_z - panel_h), (hw - 0.003, hd + 0.006, top_z - 0.002), panel_c, "plastic"),
    ]
    return parts, top_receptacle("top", top_lo, top_hi), hd, top_z - panel_h


def make_washing_machine(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.55, 0.6), rng.uniform(0.5, 0.62), rng.uniform(0.82, 0.86)
    shell = pick(rng, APPLIANCES, jitter=0.02)
    panel_c = shell if rng.random() < 0.5 else _trim(shell)
    parts, top, yf, panel_z = _laundry_shell(rng, width, depth, height, shell, panel_c)
    py = yf + 0.006  # the control strip's face
    hw = width / 2
    pz = (panel_z + height) / 2 - 0.01
    # Seen from the front (+y), +x is on the left: the detergent drawer there, then the
    # programme dial, a display and buttons toward the right (-x).
    dw = rng.uniform(0.14, 0.2)
    drawer_c = shade(panel_c, 0.92)
    parts += [block((hw - 0.02 - dw, py, panel_z + 0.015), (hw - 0.02, py + 0.008, height - 0.035), drawer_c,
                    "plastic", collision="none"),
              block((hw - 0.03 - dw * 0.5, py + 0.008, panel_z + 0.02), (hw - 0.03, py + 0.012, panel_z + 0.03),
                    (0.1, 0.1, 0.1, 1.0), "plastic", collision="none")]
    dial_c = pick(rng, METALS[:3], jitter=0.02)
    dial_x = -rng.uniform(0.0, 0.06)
    parts.append(_knob(dial_x, py, pz, rng.uniform(0.028, 0.038), 0.025, dial_c, segments=8))
    parts.append(block((-hw + 0.1, py, pz - 0.015), (dial_x - 0.05, py + 0.003, pz + 0.015), SCREEN, "glass",
                       collision="none"))
    keys = pick(rng, DARK_PLASTICS, jitter=0.02)
    parts += _buttons(-hw + 0.02, -hw + 0.095, py, pz, 2, 0.014, keys)
    # The porthole door: chrome or plain rim, clear blue-grey glass bowl.
    r_out = rng.uniform(0.16, 0.2)
    dz = panel_z - 0.04 - r_out - rng.uniform(0.0, 0.05)
    rim = pick(rng, METALS[:3] + ((0.94, 0.94, 0.93), (0.16, 0.16, 0.17)), jitter=0.02)
    parts += _porthole(0.0, yf, dz, r_out, r_out * rng.uniform(0.68, 0.78), rng.uniform(0.03, 0.045), rim,
                       pick(rng, ((0.35, 0.42, 0.5), (0.25, 0.3, 0.35)), jitter=0.05), bulge=0.02, opaque=False)
    parts.append(block((-r_out - 0.012, yf, dz - 0.04), (-r_out + 0.01, yf + 0.035, dz + 0.04), shade(rim, 0.8),
                       "plastic", collision="none"))
    return finish("washing_machine", parts, receptacles=[top],
                  names=["washing machine", "washer", "laundry machine", "clothes washer"], rooms=LAUNDRY,
                  placement="wall", front_clearance=0.8, mass=float(rng.uniform(60, 85)))


def make_dryer(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.55, 0.6), rng.uniform(0.55, 0.65), rng.uniform(0.84, 0.87)
    shell = pick(rng, APPLIANCES, jitter=0.02)
    panel_c = _trim(shell) if rng.random() < 0.6 else shade(shell, 0.9)
    parts, top, yf, panel_z = _laundry_shell(rng, width, depth, height, shell, panel_c)
    py = yf + 0.006  # the control strip's face
    hw = width / 2
    pz = (panel_z + height) / 2 - 0.01
    # A water tank drawer on the strip's left (+x, seen from the front) of a condenser dryer.
    condenser = rng.random() < 0.6
    if condenser:
        tw = rng.uniform(0.2, 0.26)
        parts += [block((hw - 0.015 - tw, py, panel_z + 0.012), (hw - 0.015, py + 0.008, height - 0.03),
                        shade(panel_c, 1.12), "plastic", collision="none"),
                  block((hw - 0.015 - tw * 0.7, py + 0.008, panel_z + 0.02),
                        (hw - 0.015 - tw * 0.3, py + 0.014, panel_z + 0.03), (0.1, 0.1, 0.1, 1.0), "plastic",
                        collision="none")]
        kx = -rng.uniform(0.04, 0.1)
    else:
        kx = hw - 0.09
    # A large programme knob ringed by indicator lights, and a row of buttons.
    knob_c = pick(rng, METALS[:3] + DARK_PLASTICS[:1], jitter=0.02)
    kr = rng.uniform(0.035, 0.045)
    parts += [_knob(kx, py, pz, kr + 0.012, 0.004, (0.9, 0.55, 0.2, 1.0)),
              _knob(kx, py, pz, kr, 0.03, knob_c)]
    parts += _buttons(-hw + 0.02, kx - kr - 0.03, py, pz, int(rng.integers(2, 4)), 0.013,
                      pick(rng, DARK_PLASTICS, jitter=0.02))
    # A big door, opaque or smoked, with a contrasting rim and a pull on the side.
    r_out = rng.uniform(0.19, 0.23)
    dz = panel_z - 0.03 - r_out
    rim = pick(rng, ((0.16, 0.16, 0.17), (0.72, 0.73, 0.75), (0.5, 0.5, 0.52)), jitter=0.02)
    opaque = rng.random() < 0.5
    window = shell if opaque else pick(rng, ((0.2, 0.2, 0.22), (0.3, 0.25, 0.2)), jitter=0.05)
    parts += _porthole(0.0, yf, dz, r_out, r_out * rng.uniform(0.78, 0.86), rng.uniform(0.025, 0.035), rim,
                       window, bulge=0.01, opaque=opaque)
    parts.append(block((-0.04, yf, dz - r_out - 0.01), (0.04, yf + 0.03, dz - r_out + 0.015), shade(rim, 0.8),
                       "plastic", collision="none"))
    # The louvred vent of the condenser or the air intake along the bottom.
    vz0, vz1 = 0.06, min(dz - r_out - 0.03, rng.uniform(0.12, 0.16))
    parts.append(block((-hw + 0.03, yf, vz0), (hw - 0.03, yf + 0.004, vz1), shade(shell, 0.75), "metal",
                       collision="none"))
    for z in np.linspace(vz0 + 0.012, vz1 - 0.012, int(rng.integers(2, 4))):
        parts.append(block((-hw + 0.04, yf + 0.004, z - 0.004), (hw - 0.04, yf + 0.012, z + 0.004),
                           shade(shell, 0.55), "metal", collision="none"))
    return finish("dryer", parts, receptacles=[top], names=["dryer", "clothes dryer", "tumble dryer"],
                  rooms=LAUNDRY, placement="wall", front_clearance=0.8, mass=float(rng.uniform(35, 50)))


def make_trash_can(rng: np.random.Generator) -> AssetModel:
    style = ("pedal", "swing", "open")[int(rng.choice(3, p=[0.45, 0.25, 0.3]))]
    body_c, body_m = ((pick(rng, METALS[:4], jitter=0.03), "metal") if rng.random() < 0.5
                      else (pick(rng, DARK_PLASTICS + CERAMICS[:4], jitter=0.03), "plastic"))
    lid_c = body_c if rng.random() < 0.6 else pick(rng, DARK_PLASTICS[:2], jitter=0.02)
    parts: list[Part] = []
    if style == "open":  # a wastebasket: an open vessel
        r, h = rng.uniform(0.11, 0.16), rng.uniform(0.26, 0.36)
        flare, t = rng.uniform(1.1, 1.25), 0.006
        seg = 12
        parts.append(lathe([(r, 0.0), (r * flare, h), (r * flare - t, h), (r - t, 0.01)], body_c, body_m,
                           segments=seg))
        names = ["trash can", "wastebasket", "waste bin", "bin"]
    elif rng.random() < 0.5:  # round, with a pedal or a swing lid
        r, h = rng.uniform(0.13, 0.2), rng.uniform(0.4, 0.7)
        parts += [lathe([(r * 0.95, 0.0), (r, 0.02), (r, h - 0.03)], body_c, body_m, segments=12),
                  lathe([(r + 0.005, h - 0.035), (r + 0.005, h - 0.01), (r * 0.7, h)], lid_c, body_m, segments=12)]
        if style == "pedal":
            parts.append(block((-0.05, r - 0.02, 0.015), (0.05, r + 0.05, 0.04), shade(lid_c, 0.8), "plastic"))
        else:
            parts.append(block((-r * 0.5, -0.04, h), (r * 0.5, 0.04, h + 0.03), shade(lid_c, 0.9), body_m))
        names = ["trash can", "garbage can", "trash bin", "bin"]
    else:  # rectangular
        w, d, h = rng.uniform(0.25, 0.4), rng.uniform(0.22, 0.32), rng.uniform(0.45, 0.75)
        hw, hd = w / 2, d / 2
        parts += [block((-hw, -hd, 0.0), (hw, hd, h - 0.04), body_c, body_m),
                  block((-hw - 0.005, -hd - 0.005, h - 0.04), (hw + 0.005, hd + 0.005, h), lid_c, body_m)]
        if style == "pedal":
            parts.append(block((-0.06, hd - 0.02, 0.015), (0.06, hd + 0.05, 0.04), shade(lid_c, 0.8), "plastic"))
        else:  # the swinging flap, darker, on the lid's front half
            parts.append(block((-hw + 0.03, 0.0, h), (hw - 0.03, hd - 0.02, h + 0.004), shade(lid_c, 0.6),
                               "plastic", collision="none"))
        names = ["trash can", "garbage can", "trash bin", "bin"]
    return finish("trash_can", parts, names=names,
                  rooms=["kitchen", "office", "bathroom", "bedroom", "living_room"], placement="corner",
                  front_clearance=0.3, mass=float(rng.uniform(1.0, 5.0)))


# ---------------------------------------------------------------------------------------
# Kitchen furniture.


def make_kitchen_island(rng: np.random.Generator) -> AssetModel:
    width, height = rng.uniform(1.2, 2.4), rng.uniform(0.88, 0.94)
    base_d = rng.uniform(0.58, 0.65)
    seating = rng.random() < 0.6  # the top overhangs the back (-y) for stools
    back_over = rng.uniform(0.25, 0.35) if seating else rng.uniform(0.02, 0.06)
    front_over = rng.uniform(0.02, 0.04)
    waterfall = rng.random() < 0.35  # the top turns down to the floor at both ends
    body = pick(rng, WOODS + CABINET_PAINTS)
    front = body if rng.random() < 0.6 else pick(rng, WOODS + CABINET_PAINTS)
    stone, handle_c = pick(rng, COUNTERTOPS), pick(rng, METALS)
    top_t = rng.uniform(0.03, 0.05)
    hw = width / 2
    under = height - top_t
    side_t = top_t if waterfall else 0.0
    bw = hw - (side_t if waterfall else rng.uniform(0.02, 0.04))  # half width of the base
    yb0, yb1 = -base_d / 2, base_d / 2
    front_y = yb1 + 0.02  # the cabinet fronts stand proud of the body
    y_lo, y_hi = yb0 - back_over, front_y + front_over
    kick = 0.1
    top_lo, top_hi = (-hw, y_lo, under), (hw, y_hi, height)
    parts = [block(top_lo, top_hi, stone, "ceramic"),
             block((-bw + 0.01, yb0 + 0.05, 0.0), (bw - 0.01, yb1 - 0.05, kick), shade(body, 0.5), "wood"),
             block((-bw, yb0, kick), (bw, yb1, under), body, "wood")]
    if waterfall:
        parts += [block((-hw, y_lo, 0.0), (-hw + side_t, y_hi, under), stone, "ceramic"),
                  block((hw - side_t, y_lo, 0.0), (hw, y_hi, under), stone, "ceramic")]
    elif seating and rng.random() < 0.5:  # posts holding up the seating overhang
        for sx in (-1, 1):
            x0, x1 = sorted((sx * (hw - 0.02), sx * (hw - 0.08)))
            parts.append(block((x0, y_lo + 0.02, 0.0), (x1, y_lo + 0.08, under), shade(body, 0.85), "wood"))
    # Fronts: columns of doors, with one or two drawer banks.
    cols = max(2, int(round(2 * bw / 0.5)))
    edges = np.linspace(-bw, bw, cols + 1)
    banks = set(rng.choice(cols, size=min(cols // 2, int(rng.integers(0, 3))), replace=False).tolist())
    bar = rng.random() < 0.6
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        mid = (a + b) / 2
        rows = np.linspace(kick, under, 4) if i in banks else np.array([kick, under])
        for z0, z1 in zip(rows[:-1], rows[1:]):
            parts.append(block((a + 0.002, yb1, z0 + 0.003), (b - 0.002, front_y, z1 - 0.003), front, "wood"))
            hz = (z0 + z1) / 2 if i in banks else z1 - 0.08
            hl = 0.06 if bar else 0.015
            parts.append(block((mid - hl, front_y, hz - 0.008), (mid + hl, front_y + 0.025, hz + 0.008), handle_c,
                               "metal", collision="none"))
    return finish("kitchen_island", parts, receptacles=[top_receptacle("top", top_lo, top_hi)],
                  names=["kitchen island", "island", "island counter", "kitchen island counter"], rooms=KITCHEN,
                  placement="middle", front_clearance=0.9, mass=float(60 + 60 * width + rng.uniform(0, 30)))


def make_bar_stool(rng: np.random.Generator) -> AssetModel:
    seat_h = rng.uniform(0.6, 0.66) if rng.random() < 0.5 else rng.uniform(0.72, 0.8)  # counter or bar height
    style = ("four", "three", "pole")[int(rng.integers(3))]
    frame_c, frame_m = ((pick(rng, WOODS[:6]), "wood") if style != "pole" and rng.random() < 0.5
                        else (pick(rng, METALS), "metal"))
    seat_c, seat_m = ((pick(rng, LEATHERS), "leather") if rng.random() < 0.4
                      else (pick(rng, FABRICS), "fabric") if rng.random() < 0.5 else (frame_c, frame_m))
    seat_t = rng.uniform(0.04, 0.07)
    foot_z = seat_h * rng.uniform(0.35, 0.45)
    round_seat = style != "four" or rng.random() < 0.5
    r = rng.uniform(0.17, 0.22)  # seat radius (or half side)
    seat_lo_z = seat_h - seat_t
    parts: list[Part] = []
    if round_seat:
        parts.append(rod(0, 0, seat_lo_z, seat_h, r, seat_c, seat_m, segments=12))
    else:
        parts.append(block((-r, -r, seat_lo_z), (r, r, seat_h), seat_c, seat_m))
    splay = rng.uniform(0.02, 0.07)  # how far the feet stand out beyond the tops of the legs
    if style == "four":
        s = r * (0.6 if round_seat else 0.85) - 0.02  # leg tops, under the seat
        leg = rng.uniform(0.025, 0.035)
        rung_s = s + splay * (1.0 - foot_z / seat_lo_z)  # where the legs pass the footrest height
        for sx in (-1, 1):
            for sy in (-1, 1):
                parts.append(_slanted(block((sx * (s + splay) - leg / 2, sy * (s + splay) - leg / 2, 0.0),
                                            (sx * (s + splay) + leg / 2, sy * (s + splay) + leg / 2, seat_lo_z),
                                            frame_c, frame_m, collision="hull"), -sx * splay, -sy * splay))
        rung = leg * 0.7
        parts += [block((-rung_s, sy * rung_s - rung / 2, foot_z - rung / 2),
                        (rung_s, sy * rung_s + rung / 2, foot_z + rung / 2), frame_c, frame_m) for sy in (-1, 1)]
        parts += [block((sx * rung_s - rung / 2, -rung_s + rung / 2, foot_z - rung / 2),
                        (sx * rung_s + rung / 2, rung_s - rung / 2, foot_z + rung / 2), frame_c, frame_m)
                  for sx in (-1, 1)]
    elif style == "three":
        lr = r * 0.75
        leg = rng.uniform(0.012, 0.018)
        for k in range(3):
            a = np.pi / 2 + 2 * np.pi * k / 3  # one leg at the front
            c, sn = np.cos(a), np.sin(a)
            parts.append(_slanted(rod((lr + splay) * c, (lr + splay) * sn, 0.0, seat_lo_z, leg, frame_c, frame_m,
                                      segments=6), -splay * c, -splay * sn))
        fr = lr + splay * (1.0 - foot_z / seat_lo_z)
        parts.append(annulus((fr + 0.012, fr + 0.012), (fr - 0.012, fr - 0.012), foot_z - 0.01, foot_z + 0.01,
                             frame_c, frame_m, segments=12))
    else:
        base_r = rng.uniform(0.19, 0.23)
        parts += [rod(0, 0, 0.0, 0.02, base_r, frame_c, frame_m, segments=12, radius_top=base_r * 0.9),
                  rod(0, 0, 0.02, seat_lo_z - 0.05, rng.uniform(0.022, 0.03), frame_c, frame_m, segments=8),
                  rod(0, 0, seat_lo_z - 0.05, seat_lo_z, 0.05, shade(frame_c, 0.8), frame_m, segments=8)]
        fr = rng.uniform(0.15, 0.18)
        parts += [annulus((fr + 0.012, fr + 0.012), (fr - 0.012, fr - 0.012), foot_z - 0.01, foot_z + 0.01,
                          frame_c, frame_m, segments=12),
                  block((-0.012, -fr, foot_z - 0.008), (0.012, fr, foot_z + 0.008), frame_c, frame_m)]
    if rng.random() < 0.45:  # a low backrest on two posts standing on the back of the seat
        back_h = rng.uniform(0.2, 0.3)
        bx, post_y = r * 0.5, -r * (0.8 if round_seat else 0.92)
        parts += [block((sx * bx - 0.012, post_y, seat_h), (sx * bx + 0.012, post_y + 0.024, seat_h + back_h),
                        frame_c, frame_m) for sx in (-1, 1)]
        parts.append(block((-bx - 0.04, post_y - 0.006, seat_h + back_h - 0.09), (bx + 0.04, post_y + 0.03,
                           seat_h + back_h), seat_c, seat_m))
    return finish("bar_stool", parts, names=["bar stool", "barstool", "counter stool", "kitchen stool"],
                  rooms=["kitchen", "dining_room", "living_room"], placement="middle", front_clearance=0.3,
                  mass=float(rng.uniform(4, 9)))


def make_pantry_cabinet(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.45, 1.0), rng.uniform(0.4, 0.6), rng.uniform(1.8, 2.25)
    body = pick(rng, WOODS + CABINET_PAINTS)
    front = body if rng.random() < 0.7 else pick(rng, WOODS + CABINET_PAINTS)
    handle_c = pick(rng, METALS)
    t, door_t, plinth = 0.018, 0.02, rng.uniform(0.08, 0.12)
    hw, hd = width / 2, depth / 2
    yf = hd - door_t
    inner = shade(body, 0.92)
    parts = [
        block((-hw, -hd, 0.0), (-hw + t, yf, height), body, "wood"),
        block((hw - t, -hd, 0.0), (hw, yf, height), body, "wood"),
        block((-hw + t, -hd, height - t), (hw - t, yf, height), body, "wood"),
        block((-hw + t, -hd, plinth), (hw - t, -hd + 0.008, height - t), inner, "wood"),
        block((-hw + t, -hd + 0.008, 0.0), (hw - t, yf - 0.03, plinth), shade(body, 0.6), "wood"),
    ]
    if rng.random() < 0.4:  # a cornice on top, overhanging the doors
        parts.append(block((-hw - 0.015, -hd, height), (hw + 0.015, hd + 0.015, height + rng.uniform(0.03, 0.05)),
                           shade(body, 0.95), "wood"))
    ceiling = height - t
    levels = int(rng.integers(4, 7))  # shelves, the bottom board included
    zs = np.linspace(plinth, ceiling, levels + 1)[:-1]
    recs = []
    for i, z in enumerate(zs):
        lo, hi = (-hw + t, -hd + 0.008, z), (hw - t, yf - 0.005, z + t)
        parts.append(block(lo, hi, inner, "wood"))
        above = zs[i + 1] if i + 1 < len(zs) else ceiling
        recs.append(top_receptacle(f"shelf_{i}", lo, hi, clearance=float(above - hi[2])))
    doors = 1 if width < 0.6 else 2
    edges = np.linspace(-hw, hw, doors + 1)
    panel = shade(front, 0.9) if rng.random() < 0.5 else None
    handle = "bar" if rng.random() < 0.6 else "knob"
    single_left = rng.random() < 0.5
    moving = [hinged_door(f"door_{i}", float(edges[i]) + 0.002, float(edges[i + 1]) - 0.002, yf, plinth,
                          height - 0.003, hinge_left=(i == 0) if doors == 2 else single_left, rgba=front,
                          material="wood", handle=_cabinet_pull(handle, handle_c), thickness=door_t,
                          handle_z=min(1.05, height * 0.5), handle_inset=0.045, panel=panel)
              for i in range(doors)]
    door_w = float(edges[1] - edges[0])
    return finish("pantry_cabinet", parts, moving=moving, receptacles=recs,
                  names=["pantry cabinet", "pantry", "larder", "kitchen cabinet", "pantry cupboard"],
                  rooms=KITCHEN, placement="wall", front_clearance=max(0.8, door_w + 0.1),
                  mass=float(rng.uniform(40, 60) * width * height / 1.4))


FACTORIES = {
    "stove": make_stove,
    "microwave": make_microwave,
    "dishwasher": make_dishwasher,
    "washing_machine": make_washing_machine,
    "dryer": make_dryer,
    "kitchen_island": make_kitchen_island,
    "bar_stool": make_bar_stool,
    "trash_can": make_trash_can,
    "pantry_cabinet": make_pantry_cabinet,
    "coffee_machine": make_coffee_machine,
    "toaster": make_toaster,
}

register_builtins(FACTORIES)
