"""Built-in bathroom fixtures and standing decor (parametric, seeded, low-poly; registered on import).

Bathroom: shower, vanity (hinged doors, basin and counter receptacles), towel rack, laundry
hamper. Standing decor and room fittings: standing mirror, fireplace (mantel receptacle),
aquarium (lid receptacle), floor fan, radiator (top or shelf receptacle on some variants),
umbrella stand, grandfather clock (top receptacle on flat-topped variants).

The conventions are those of :mod:`legent_gym.world.assets.library.furniture`. Glass and water
render opaque, so what is seen through them (the aquarium's sand, plants and fish, the clock's
pendulum) lies as thin decorative parts just in front of the tinted surface.
"""

from __future__ import annotations

import numpy as np

from legent_gym.world.assets.library.common import (
    APPLIANCES,
    CERAMICS,
    COUNTERTOPS,
    DARK_PLASTICS,
    FABRICS,
    FOLIAGE,
    GLASSES,
    METALS,
    RGBA,
    WHITE,
    WICKERS,
    WOODS,
    Colours,
    Handle,
    along_x,
    along_y,
    annulus,
    block,
    finish,
    hinged_door,
    lathe,
    legs,
    pick,
    register_builtins,
    rod,
    shade,
    top_receptacle,
    transformed,
    wood_or_metal,
)
from legent_gym.world.assets.model import AssetModel, Collision, Part, Receptacle

TRAYS: Colours = (
    (0.95, 0.95, 0.93),  # white acrylic
    (0.90, 0.88, 0.82),  # cream
    (0.62, 0.62, 0.60),  # grey stone resin
    (0.22, 0.22, 0.24),  # slate
)
#: The lighter, barely tinted glasses of shower screens.
SCREEN_GLASSES: Colours = (GLASSES[0], GLASSES[3], (0.84, 0.88, 0.88))
#: Mirror surfaces: a light grey-blue that reads as a reflection.
MIRRORS: Colours = ((0.74, 0.80, 0.86), (0.68, 0.75, 0.82), (0.80, 0.84, 0.88))
BRICKS: Colours = (
    (0.62, 0.30, 0.22),  # red brick
    (0.52, 0.24, 0.19),  # dark red
    (0.72, 0.50, 0.36),  # buff
    (0.44, 0.32, 0.27),  # brown
)
#: Dressed stone of fireplace surrounds and hearths (and the aquarium's rocks).
BUILDING_STONES: Colours = (
    (0.72, 0.70, 0.66),  # limestone
    (0.56, 0.55, 0.53),  # grey
    (0.84, 0.80, 0.72),  # sandstone
    (0.90, 0.89, 0.87),  # marble
)
#: Painted finishes of vanity units and fireplace surrounds besides wood and stone.
FITTING_PAINTS: Colours = (
    (0.95, 0.95, 0.93),  # white
    (0.90, 0.87, 0.80),  # cream
    (0.60, 0.66, 0.58),  # sage
    (0.33, 0.36, 0.40),  # charcoal blue
)
WATERS: Colours = ((0.42, 0.68, 0.80), (0.34, 0.60, 0.78), (0.48, 0.74, 0.72))
SANDS: Colours = ((0.86, 0.78, 0.60), (0.80, 0.72, 0.55), (0.72, 0.68, 0.62))
FISH: Colours = ((0.96, 0.55, 0.10), (0.96, 0.82, 0.15), (0.86, 0.20, 0.15), (0.20, 0.45, 0.92))
RADIATORS: Colours = (
    (0.95, 0.95, 0.94),  # white
    (0.90, 0.89, 0.86),  # off-white
    (0.62, 0.63, 0.65),  # grey
    (0.22, 0.23, 0.25),  # anthracite
)
SOOT: RGBA = (0.07, 0.06, 0.06, 1.0)
GLOW: RGBA = (0.95, 0.45, 0.10, 1.0)


# ---------------------------------------------------------------------------------------
# Part builders the shared ones lack: horizontal bars, rings facing the front, struts.


def _bar_x(x0: float, x1: float, y: float, z: float, radius: float, rgba: RGBA, material: str, *,
           segments: int = 8, collision: Collision = "hull") -> Part:
    """A horizontal cylinder from ``x0`` to ``x1`` on the line (y, z)."""
    return along_x(rod(y, z, x0, x1, radius, rgba, material, segments=segments, collision=collision))


def _bar_y(x: float, y0: float, y1: float, z: float, radius: float, rgba: RGBA, material: str, *,
           segments: int = 8, collision: Collision = "hull", radius_end: float | None = None) -> Part:
    """A horizontal cylinder (or frustum ending in ``radius_end``) from ``y0`` to ``y1`` on the
    line (x, z): rods, arms and discs that face the front."""
    return along_y(rod(z, x, y0, y1, radius, rgba, material, segments=segments, collision=collision,
                       radius_top=radius_end))


def _ring_y(x: float, z: float, y0: float, y1: float, r_out: float, r_in: float, rgba: RGBA,
            material: str, *, segments: int = 12, collision: Collision = "none") -> Part:
    """A flat ring facing the front (a fan guard), centred on (x, z), from ``y0`` to ``y1``."""
    # Built in a frame whose z is the asset's y, then turned by along_y.
    return along_y(annulus((r_out, r_out), (r_in, r_in), y0, y1, rgba, material, centre=(z, x), segments=segments,
                           collision=collision))


def _square_strut(p0: tuple[float, float, float], p1: tuple[float, float, float], width: float, thick: float,
                  rgba: RGBA, material: str, *, collision: Collision = "hull") -> Part:
    """A square-ish bar from ``p0`` to ``p1``, which differ only in y and z (an easel leg)."""
    # Not living's _strut: that one is a round bar between any two points, built another way.
    dy, dz = p1[1] - p0[1], p1[2] - p0[2]
    length = float(np.hypot(dy, dz))
    bar = block((-width / 2, -thick / 2, -length / 2), (width / 2, thick / 2, length / 2), rgba, material,
                collision=collision)
    mid = (p0[0], (p0[1] + p1[1]) / 2, (p0[2] + p1[2]) / 2)
    return transformed(bar, rotate_x=float(np.arctan2(-dy, dz)), offset=mid)


def _vanity_pull(style: str, rgba: RGBA) -> Handle:
    """A vanity door's handle: "bar" (a slim vertical pull, 40 % of the door's height and at
    most 16 cm long) or "knob"."""
    def make(x: float, y: float, z: float, height: float) -> list[Part]:
        if style == "bar":
            hl = min(0.16, 0.4 * height) / 2
            return [block((x - 0.006, y, z - hl), (x + 0.006, y + 0.025, z + hl), rgba, "metal")]
        return [block((x - 0.012, y, z - 0.012), (x + 0.012, y + 0.025, z + 0.012), rgba, "metal")]
    return make


# ---------------------------------------------------------------------------------------
# Bathroom.


def make_shower(rng: np.random.Generator) -> AssetModel:
    width = rng.uniform(0.8, 1.0)
    depth = width if rng.random() < 0.5 else rng.uniform(0.8, 1.0)
    tray_h = rng.uniform(0.04, 0.12)
    tray, glass, metal = pick(rng, TRAYS, jitter=0.03), shade(pick(rng, SCREEN_GLASSES, jitter=0.03), 1.1), pick(rng, METALS)
    # Panes thicker than real glass: thin slabs show shadow stripes in the renderer.
    panel_h, t = rng.uniform(1.85, 2.0), 0.025
    hw, hd = width / 2, depth / 2
    top = tray_h + panel_h
    parts = [block((-hw, -hd, 0.0), (hw, hd, tray_h), tray, "ceramic"),
             rod(rng.uniform(-0.15, 0.15) * width, rng.uniform(-0.1, 0.1) * depth, tray_h, tray_h + 0.003,
                 0.045, metal, "metal", collision="none")]
    yg = hd - 0.03  # the screen's plane stands a little in from the tray's front edge
    style = rng.choice(["walk_in", "sliding", "corner"])
    if style == "walk_in":  # one fixed pane across part of the front, braced to the back wall
        span = width * rng.uniform(0.55, 0.75)
        x0, x1 = (-hw, -hw + span) if rng.random() < 0.5 else (hw - span, hw)
        parts += [block((x0, yg - t, tray_h), (x1, yg, top), glass, "glass"),
                  _bar_y(x1 - 0.02 if x0 == -hw else x0 + 0.02, -hd, yg - t, top - 0.03, 0.01, metal, "metal")]
        panes = [(x1 - x0, panel_h)]
    elif style == "sliding":  # a fixed pane and a door pane just in front of it, on a top rail
        split = rng.uniform(-0.08, 0.08)
        parts += [block((-hw + 0.01, yg - 2 * t - 0.01, tray_h), (split + 0.05, yg - t - 0.01, top), glass, "glass"),
                  block((split - 0.05, yg - t, tray_h), (hw - 0.01, yg, top), glass, "glass"),
                  block((-hw, yg - 2 * t - 0.02, top), (hw, yg + 0.005, top + 0.03), metal, "metal"),
                  block((split - 0.04, yg, tray_h + 0.9), (split - 0.02, yg + 0.03, tray_h + 1.2), metal, "metal")]
        panes = [(width, panel_h)]
    else:  # a front pane with a door gap, and a side pane
        side = 1.0 if rng.random() < 0.5 else -1.0
        gap = rng.uniform(0.5, 0.6)
        xf0, xf1 = sorted((side * hw, side * (hw - (width - gap))))
        xs0, xs1 = sorted((side * hw, side * (hw - t)))
        parts += [block((xf0, yg - t, tray_h), (xf1, yg, top), glass, "glass"),
                  block((xs0, -hd + 0.02, tray_h), (xs1, yg - t, top), glass, "glass"),
                  rod(side * (hw - t / 2), yg - t / 2, tray_h, top, 0.012, metal, "metal", segments=6)]
        panes = [(width - gap, panel_h), (depth, panel_h)]
    # The riser on the back wall, a mixer halfway up and the head on an arm.
    rx = rng.uniform(-0.2, 0.2) * width
    ry = -hd + 0.04
    riser_top = tray_h + rng.uniform(1.9, 2.05)
    arm = rng.uniform(0.2, 0.35)
    hz = riser_top - 0.02
    parts += [rod(rx, ry, tray_h + 0.9, riser_top, 0.012, metal, "metal", segments=6),
              block((rx - 0.06, -hd, tray_h + 0.95), (rx + 0.06, -hd + 0.06, tray_h + 1.05), metal, "metal"),
              _bar_y(rx + 0.05, -hd + 0.06, -hd + 0.12, tray_h + 1.0, 0.01, metal, "metal", segments=6,
                     collision="none"),
              _bar_y(rx, ry, ry + arm, hz, 0.01, metal, "metal", segments=6)]
    head = rng.uniform(0.08, 0.14)
    if rng.random() < 0.5:
        parts.append(rod(rx, ry + arm, hz - 0.03, hz, head, metal, "metal", segments=12))
    else:
        parts.append(block((rx - head, ry + arm - head, hz - 0.025), (rx + head, ry + arm + head, hz), metal, "metal"))
    glass_kg = sum(w * h for w, h in panes) * 0.008 * 2500.0
    return finish("shower", parts, names=["shower", "shower stall", "shower cubicle", "shower enclosure"],
                  rooms=["bathroom"], placement="corner", front_clearance=0.7,
                  mass=float(glass_kg + rng.uniform(20, 40)))


def make_vanity(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.6, 1.2), rng.uniform(0.45, 0.55), rng.uniform(0.8, 0.9)
    body = pick(rng, WOODS + APPLIANCES[:1] + FITTING_PAINTS[2:])
    front = body if rng.random() < 0.6 else pick(rng, WOODS + FITTING_PAINTS)
    handle, stone = pick(rng, METALS), pick(rng, COUNTERTOPS)
    basin_c = pick(rng, CERAMICS[:2] + ((0.95, 0.95, 0.94),), jitter=0.02)
    top_t, t, door_t = rng.uniform(0.02, 0.04), 0.018, 0.02
    hw, hd = width / 2, depth / 2
    under = height - top_t  # the countertop's underside, the carcass's top
    yf = hd - 0.02 - door_t  # the carcass front; the doors stand in front of it
    if rng.random() < 0.5:  # a toe kick
        base_z = rng.uniform(0.08, 0.12)
        parts = [block((-hw + 0.02, -hd, 0.0), (hw - 0.02, yf - 0.04, base_z), shade(body, 0.5), "wood")]
    else:  # short legs
        base_z = rng.uniform(0.12, 0.22)
        leg_c, leg_m = (pick(rng, METALS), "metal") if rng.random() < 0.6 else (shade(body, 0.8), "wood")
        parts = legs(-hw + 0.01, hw - 0.01, -hd + 0.01, yf - 0.01, 0.0, base_z, 0.04, leg_c, leg_m)
    parts += [block((-hw, -hd, base_z), (-hw + t, yf, under), body, "wood"),
              block((hw - t, -hd, base_z), (hw, yf, under), body, "wood"),
              block((-hw + t, -hd, base_z), (hw - t, -hd + t, under), body, "wood"),
              block((-hw + t, -hd + t, base_z), (hw - t, yf, base_z + t), body, "wood")]
    splash = rng.uniform(0.06, 0.12) if rng.random() < 0.4 else 0.0
    y_back = -hd + (0.02 if splash else 0.0)  # where the free counter starts
    if splash:
        parts.append(block((-hw, -hd, height), (hw, -hd + 0.02, height + splash), stone, "ceramic"))
    bw = min(width - 0.2, rng.uniform(0.36, 0.5)) / 2
    yb1 = hd - rng.uniform(0.05, 0.08)
    yb0 = max(-hd + 0.1, yb1 - rng.uniform(0.3, 0.36))
    wall = 0.013
    tap = pick(rng, METALS[:3] + METALS[4:])
    fy = (y_back + yb0) / 2
    if rng.random() < 0.5:  # undermount: the countertop in four strips around the basin's mouth
        floor = height - rng.uniform(0.13, 0.17)
        rim = height - 0.003
        parts += [block((-hw, yb1, under), (hw, hd, height), stone, "ceramic"),
                  block((-hw, -hd, under), (hw, yb0, height), stone, "ceramic"),
                  block((-hw, yb0, under), (-bw, yb1, height), stone, "ceramic"),
                  block((bw, yb0, under), (hw, yb1, height), stone, "ceramic")]
        bz0 = floor - wall
    else:  # a vessel basin standing on a whole countertop
        bz0 = height
        floor = height + wall
        rim = height + rng.uniform(0.11, 0.15)
        parts.append(block((-hw, -hd, under), (hw, hd, height), stone, "ceramic"))
    parts += [block((-bw, yb0, bz0), (bw, yb1, floor), basin_c, "ceramic"),
              block((-bw, yb0, floor), (-bw + wall, yb1, rim), basin_c, "ceramic"),
              block((bw - wall, yb0, floor), (bw, yb1, rim), basin_c, "ceramic"),
              block((-bw + wall, yb0, floor), (bw - wall, yb0 + wall, rim), basin_c, "ceramic"),
              block((-bw + wall, yb1 - wall, floor), (bw - wall, yb1, rim), basin_c, "ceramic")]
    # The spout reaches over the basin above its rim.
    fh = max(rim - height, 0.0) + rng.uniform(0.12, 0.2)
    parts += [rod(0.0, fy, height, height + fh, 0.015, tap, "metal"),
              block((-0.011, fy, height + fh - 0.025), (0.011, yb0 + 0.09, height + fh), tap, "metal"),
              block((0.015, fy - 0.008, height + fh - 0.06), (0.07, fy + 0.008, height + fh - 0.045), tap, "metal",
                    collision="none")]
    recs = [top_receptacle("basin", (-bw + wall, yb0 + wall, 0.0), (bw - wall, yb1 - wall, floor),
                           clearance=rim - floor)]
    if hw - bw >= 0.16:
        recs += [top_receptacle("counter_left", (-hw, y_back, 0.0), (-bw, hd, height)),
                 top_receptacle("counter_right", (bw, y_back, 0.0), (hw, hd, height))]
    doors = 1 if width < 0.75 else 2
    edges = np.linspace(-hw, hw, doors + 1)
    style = "bar" if rng.random() < 0.6 else "knob"
    hinge_left = rng.random() < 0.5
    d0, d1 = base_z + 0.003, under - 0.003
    moving = [hinged_door(f"door_{i}", edges[i] + 0.002, edges[i + 1] - 0.002, yf, d0, d1,
                          hinge_left=(i == 0) if doors == 2 else hinge_left, rgba=front, material="wood",
                          handle=_vanity_pull(style, handle), thickness=door_t, handle_z=d1 - 0.1,
                          handle_inset=0.045)
              for i in range(doors)]
    door_w = float(edges[1] - edges[0])
    return finish("vanity", parts, moving=moving, receptacles=recs,
                  names=["vanity", "bathroom vanity", "vanity unit", "vanity cabinet"], rooms=["bathroom"],
                  placement="wall", front_clearance=max(0.7, door_w + 0.1), mass=float(rng.uniform(30, 70)))


def make_towel_rack(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.5, 0.85), rng.uniform(0.28, 0.42), rng.uniform(0.8, 1.1)
    color, material = wood_or_metal(rng, 0.5)
    round_bars = material == "metal" or rng.random() < 0.5
    post = 0.03 if material == "wood" else 0.02
    hw, hd = width / 2, depth / 2
    parts: list[Part] = []
    bars: list[tuple[float, float]] = []  # (y, z) of each bar
    n = int(rng.integers(2, 4))
    if rng.random() < 0.5:  # upright sides on flat feet, the bars stacked above each other
        for sx in (-1.0, 1.0):
            x0, x1 = sorted((sx * hw, sx * (hw - post)))
            parts += [block((x0, -hd, 0.0), (x1, hd, 0.025), color, material),
                      block((x0, -post / 2, 0.025), (x1, post / 2, height), color, material)]
        bars = [(0.0, float(z)) for z in np.linspace(height - 0.03, height * rng.uniform(0.35, 0.5), n)]
    else:  # A-frame sides: two splayed legs each, bars on both faces and across the middle
        for sx in (-1.0, 1.0):
            x = sx * (hw - post / 2)
            for sy in (-1.0, 1.0):
                parts.append(_square_strut((x, sy * (hd - post / 2), 0.0), (x, sy * 0.05, height), post, post,
                                           color, material))
        bars = [(-0.06, height - 0.05), (0.06, height - 0.05)]
        if n == 3:  # a lower bar on the front legs, where they have splayed out
            z = height * rng.uniform(0.4, 0.55)
            bars.append((hd - post / 2 + (0.05 - hd + post / 2) * z / height, z))
    radius = rng.uniform(0.009, 0.014)
    for y, z in bars:
        if round_bars:
            parts.append(_bar_x(-hw + post, hw - post, y, z, radius, color, material, segments=8))
        else:
            parts.append(block((-hw + post, y - radius, z - radius), (hw - post, y + radius, z + radius), color,
                               material))
    # Towels draped over some bars, hanging down on both sides of them, clear of the bar below.
    for y, z in bars[:int(rng.integers(0, 3))]:
        tw = min(2 * hw - 2 * post - 0.04, rng.uniform(0.3, 0.55))
        tx = rng.uniform(-1, 1) * (hw - post - 0.02 - tw / 2)
        below = [z2 for y2, z2 in bars if abs(y2 - y) < 0.03 and z2 < z]
        drop = min(z - (max(below) + radius + 0.03 if below else 0.1), rng.uniform(0.25, 0.45))
        parts.append(block((tx - tw / 2, y - radius - 0.01, z - drop), (tx + tw / 2, y + radius + 0.01, z + radius + 0.006),
                           pick(rng, FABRICS + ((0.95, 0.95, 0.93),)), "fabric"))
    return finish("towel_rack", parts, names=["towel rack", "towel stand", "towel rail", "towel holder"],
                  rooms=["bathroom"], placement="wall", front_clearance=0.4, mass=float(rng.uniform(2, 7)))


def make_laundry_hamper(rng: np.random.Generator) -> AssetModel:
    height = rng.uniform(0.5, 0.7)
    lidded = rng.random() < 0.5
    style = rng.choice(["round", "square", "bag"])
    weave = pick(rng, WICKERS) if style != "bag" else pick(rng, FABRICS)
    material = "fabric" if style == "bag" else "wood"
    band = shade(weave, 0.8)
    clothes = pick(rng, FABRICS, jitter=0.1)
    parts: list[Part]
    if style == "round":
        r = rng.uniform(0.18, 0.26)
        rb = r * rng.uniform(0.8, 0.95)
        if lidded:
            parts = [lathe([(rb, 0.0), (r, height)], weave, material, segments=10),
                     lathe([(r + 0.012, height), (r + 0.012, height + 0.025), (r * 0.3, height + 0.04)],
                           band, material, segments=10),
                     rod(0.0, 0.0, height + 0.04, height + 0.07, 0.02, band, material, segments=6, collision="none")]
        else:
            parts = [lathe([(rb, 0.0), (r, height), (r - 0.012, height), (rb - 0.012, 0.02)], weave, material,
                           segments=10),
                     rod(0.0, 0.0, height - 0.18, height - 0.08, r * 0.7, clothes, "fabric", segments=7,
                         collision="none")]
        for z in (height * 0.3, height * 0.7):
            rz = rb + (r - rb) * z / height + 0.004
            parts.append(lathe([(rz, z), (rz, z + 0.025)], band, material, segments=10, collision="none"))
        hz = height - 0.07
        for sx in (-1.0, 1.0):
            parts.append(block((sx * (r - 0.01) - 0.012, -0.05, hz), (sx * (r - 0.01) + 0.012, 0.05, hz + 0.025),
                               shade(weave, 0.55), material, collision="none"))
    else:
        w, d = rng.uniform(0.35, 0.55), rng.uniform(0.3, 0.42)
        hw, hd, t = w / 2, d / 2, 0.025
        z0 = 0.0
        parts = []
        if style == "bag":  # a fabric bag hung in a frame of four posts
            frame, fm = wood_or_metal(rng, 0.5)
            z0 = rng.uniform(0.06, 0.12)
            parts += legs(-hw - 0.02, hw + 0.02, -hd - 0.02, hd + 0.02, 0.0, height + 0.01, 0.022, frame, fm,
                          round_legs=fm == "metal")
        parts += [block((-hw, -hd, z0), (hw, hd, z0 + t), weave, material),
                  block((-hw, -hd, z0 + t), (-hw + t, hd, height), weave, material),
                  block((hw - t, -hd, z0 + t), (hw, hd, height), weave, material),
                  block((-hw + t, -hd, z0 + t), (hw - t, -hd + t, height), weave, material),
                  block((-hw + t, hd - t, z0 + t), (hw - t, hd, height), weave, material)]
        if style == "square":  # woven bands around the outside
            for z in (height * 0.35, height * 0.7):
                parts.append(block((-hw - 0.004, -hd - 0.004, z), (hw + 0.004, hd + 0.004, z + 0.025), band,
                                   material, collision="none"))
        if lidded:
            parts += [block((-hw - 0.01, -hd - 0.01, height), (hw + 0.01, hd + 0.01, height + 0.025), band, material),
                      block((-0.05, -0.012, height + 0.025), (0.05, 0.012, height + 0.045), shade(band, 0.8),
                            material, collision="none")]
        else:
            parts.append(block((-hw + t, -hd + t, height - 0.2), (hw - t, hd - t, height - 0.06), clothes, "fabric",
                               collision="none"))
    return finish("laundry_hamper", parts, names=["laundry hamper", "hamper", "laundry basket", "clothes hamper"],
                  rooms=["bathroom", "bedroom"], placement="corner", front_clearance=0.4,
                  mass=float(rng.uniform(1.5, 5.0)))


# ---------------------------------------------------------------------------------------
# Standing decor and room fittings.


def make_standing_mirror(rng: np.random.Generator) -> AssetModel:
    mw, mh = rng.uniform(0.4, 0.7), rng.uniform(1.3, 1.65)
    frame, fmat = wood_or_metal(rng, 0.6)
    glass = pick(rng, MIRRORS, jitter=0.03)
    fw, ft = rng.uniform(0.025, 0.07), rng.uniform(0.035, 0.05)
    style = rng.choice(["leaning", "cheval", "easel"])
    oval = style == "cheval" and rng.random() < 0.5
    tilt = {"leaning": rng.uniform(0.1, 0.16), "cheval": rng.uniform(0.0, 0.06), "easel": rng.uniform(0.08, 0.14)}[style]
    lift = rng.uniform(0.15, 0.3) if style == "cheval" else 0.0
    hw = mw / 2
    # The framed glass, standing on its bottom edge at z = 0, facing +y.
    if oval:
        face = [along_y(lathe([(1.0, -ft / 2), (1.0, ft / 2)], frame, fmat, segments=16,
                              center=(mh / 2, 0.0, 0.0), scale_xy=(mh / 2, hw))),
                along_y(lathe([(1.0, -ft / 2 + 0.002), (1.0, ft / 2 + 0.003)], glass, "glass", segments=16,
                              center=(mh / 2, 0.0, 0.0), scale_xy=(mh / 2 - fw, hw - fw), collision="none"))]
    else:
        face = [block((-hw, -ft / 2, 0.0), (-hw + fw, ft / 2, mh), frame, fmat),
                block((hw - fw, -ft / 2, 0.0), (hw, ft / 2, mh), frame, fmat),
                block((-hw + fw, -ft / 2, 0.0), (hw - fw, ft / 2, fw), frame, fmat),
                block((-hw + fw, -ft / 2, mh - fw), (hw - fw, ft / 2, mh), frame, fmat),
                block((-hw + fw, -ft / 2, fw), (hw - fw, ft / 2 - 0.005, mh - fw), glass, "glass")]
    if tilt:  # the top leans back toward the wall
        face = [transformed(p, rotate_x=tilt) for p in face]
        face = [Part.exact(p.vertices, p.faces, p.rgba, "hull" if p.collision == "box" else p.collision,
                           material=p.material) for p in face]
    parts = [transformed(p, offset=(0.0, 0.0, lift)) for p in face]
    if style == "cheval":  # two uprights on feet, pivots at the mirror's middle
        post, pz = rng.uniform(0.03, 0.045), lift + mh * rng.uniform(0.55, 0.7)
        foot = rng.uniform(0.18, 0.25)
        for sx in (-1.0, 1.0):
            x0, x1 = sorted((sx * (hw + 0.012), sx * (hw + 0.012 + post)))
            p0, p1 = sorted((sx * hw, sx * (hw + 0.012)))
            parts += [block((x0, -post / 2, 0.0), (x1, post / 2, pz + 0.04), frame, fmat),
                      block((x0 - 0.005, -foot, 0.0), (x1 + 0.005, foot, 0.035), frame, fmat),
                      _bar_x(p0, p1, 0.0, pz, 0.01, shade(frame, 0.7), fmat, segments=6, collision="none")]
        if rng.random() < 0.5:  # a stretcher low between the feet
            parts.append(block((-hw - 0.012, -0.015, 0.05), (hw + 0.012, 0.015, 0.08), frame, fmat))
    elif style == "easel":  # a back leg from high on the frame down to the floor behind
        top_y = -np.sin(tilt) * mh * 0.8 - ft / 2
        leg_y = top_y - rng.uniform(0.28, 0.38)
        parts.append(_square_strut((0.0, top_y - 0.012, np.cos(tilt) * mh * 0.8), (0.0, leg_y, 0.0), 0.035,
                                   0.024, frame, fmat))
    return finish("standing_mirror", parts,
                  names=["standing mirror", "floor mirror", "full-length mirror", "cheval mirror"]
                  if style == "cheval" else ["standing mirror", "floor mirror", "full-length mirror"],
                  rooms=["bedroom", "hallway"], placement="corner", front_clearance=0.6,
                  mass=float(rng.uniform(8, 20)))


def make_fireplace(rng: np.random.Generator) -> AssetModel:
    width, body_d, height = rng.uniform(1.0, 1.6), rng.uniform(0.25, 0.42), rng.uniform(1.0, 1.3)
    style = rng.choice(["brick", "stone", "painted"])
    if style == "brick":
        surround, smat = pick(rng, BRICKS), "ceramic"
    elif style == "stone":
        surround, smat = pick(rng, BUILDING_STONES), "ceramic"
    else:
        surround, smat = pick(rng, FITTING_PAINTS), "wood"
    mantel, mmat = (pick(rng, WOODS[:6]), "wood") if rng.random() < 0.5 else (shade(surround, 0.92), smat)
    hearth_c = pick(rng, BUILDING_STONES + ((0.2, 0.2, 0.21),))
    mantel_t, over = rng.uniform(0.05, 0.09), rng.uniform(0.02, 0.08)
    hearth_h, hearth_d = rng.uniform(0.03, 0.08), rng.uniform(0.25, 0.4)
    ow = width * rng.uniform(0.45, 0.6) / 2  # half width of the opening
    open_top = rng.uniform(0.55, 0.7) * (height - mantel_t)
    hw, body_top = width / 2, height - mantel_t
    recess = rng.uniform(0.14, min(0.26, body_d - 0.06))  # how deep the firebox goes
    parts = [
        block((-hw, 0.0, 0.0), (-ow, body_d, body_top), surround, smat),
        block((ow, 0.0, 0.0), (hw, body_d, body_top), surround, smat),
        block((-ow, 0.0, open_top), (ow, body_d, body_top), surround, smat),
        block((-ow, 0.0, 0.0), (ow, body_d - recess, open_top), SOOT, "ceramic"),
        block((-ow, body_d - recess, 0.0), (ow, body_d, hearth_h), shade(SOOT, 2.0), "ceramic"),
        block((-ow - 0.15, body_d, 0.0), (ow + 0.15, body_d + hearth_d, hearth_h), hearth_c, "ceramic"),
    ]
    mantel_lo, mantel_hi = (-hw - over, -0.0, body_top), (hw + over, body_d + rng.uniform(0.03, 0.08), height)
    parts.append(block(mantel_lo, mantel_hi, mantel, mmat))
    if style == "painted":  # a plinth and pilasters proud of the face
        pil = rng.uniform(0.08, 0.14)
        for sx in (-1.0, 1.0):
            x0, x1 = sorted((sx * (ow + 0.03), sx * (ow + 0.03 + pil)))
            parts.append(block((x0, body_d, 0.0), (x1, body_d + 0.025, body_top - 0.02), shade(surround, 1.04), smat))
    elif style == "stone" and rng.random() < 0.6:  # a keystone over the opening
        parts.append(block((-0.06, body_d, open_top - 0.02), (0.06, body_d + 0.02, open_top + 0.12),
                           shade(surround, 0.9), smat))
    else:  # corbels under the mantel's ends
        for sx in (-1.0, 1.0):
            x0, x1 = sorted((sx * (hw - 0.04), sx * (hw - 0.11)))
            parts.append(block((x0, body_d, body_top - 0.12), (x1, body_d + 0.04, body_top), mantel, mmat))
    if rng.random() < 0.7:  # logs on a grate, embers under them
        log_r = rng.uniform(0.035, 0.05)
        ly = body_d - recess / 2
        lz = hearth_h + 0.04 + log_r
        lw = min(ow - 0.05, rng.uniform(0.2, 0.3))
        iron = (0.12, 0.12, 0.13, 1.0)
        parts += [block((-lw, ly - 0.08, hearth_h), (-lw + 0.02, ly + 0.08, hearth_h + 0.05), iron, "metal"),
                  block((lw - 0.02, ly - 0.08, hearth_h), (lw, ly + 0.08, hearth_h + 0.05), iron, "metal"),
                  block((-lw * 0.8, ly - 0.05, hearth_h), (lw * 0.8, ly + 0.05, hearth_h + 0.02), GLOW, "plain",
                        collision="none")]
        wood = pick(rng, WOODS[1:3] + WOODS[5:6])
        parts += [_bar_x(-lw, lw, ly - 0.035, lz, log_r, wood, "wood", segments=7),
                  _bar_x(-lw * 0.9, lw * 0.9, ly + 0.035, lz, log_r * 0.9, shade(wood, 0.85), "wood", segments=7)]
        if rng.random() < 0.5:
            parts.append(_bar_x(-lw * 0.7, lw * 0.7, ly, lz + 1.6 * log_r, log_r * 0.85, shade(wood, 1.1), "wood",
                                segments=7))
    density = 1800.0 if smat == "ceramic" else 600.0
    mass = density * width * body_d * body_top * 0.35 + 40.0
    return finish("fireplace", parts, receptacles=[top_receptacle("mantel", mantel_lo, mantel_hi)],
                  names=["fireplace", "mantelpiece", "hearth", "chimneypiece"], rooms=["living_room"],
                  placement="wall", front_clearance=0.6, mass=float(mass))


def make_aquarium(rng: np.random.Generator) -> AssetModel:
    width, depth = rng.uniform(0.6, 1.4), rng.uniform(0.3, 0.5)
    stand_h, tank_h = rng.uniform(0.6, 0.8), rng.uniform(0.3, 0.55)
    wood, handle = pick(rng, WOODS + DARK_PLASTICS[:1]), pick(rng, METALS)
    trim = pick(rng, DARK_PLASTICS[:2] + WOODS[5:6], jitter=0.03)
    water, sand = pick(rng, WATERS, jitter=0.04), pick(rng, SANDS)
    hw, hd = width / 2, depth / 2
    top_t = 0.025
    if rng.random() < 0.6:  # a cabinet with doors
        kick = rng.uniform(0.05, 0.1)
        parts = [block((-hw + 0.02, -hd, 0.0), (hw - 0.02, hd - 0.04, kick), shade(wood, 0.6), "wood"),
                 block((-hw, -hd, kick), (hw, hd - 0.02, stand_h - top_t), wood, "wood"),
                 block((-hw, -hd, stand_h - top_t), (hw, hd, stand_h), wood, "wood")]
        doors = 2 if width > 0.8 else 1
        edges = np.linspace(-hw, hw, doors + 1)
        for i in range(doors):
            a, b = edges[i] + 0.003, edges[i + 1] - 0.003
            parts.append(block((a, hd - 0.02, kick + 0.003), (b, hd, stand_h - top_t - 0.003), shade(wood, 1.05),
                               "wood"))
            hx = b - 0.05 if (doors == 1 or i == 0) else a + 0.05
            hz = stand_h - top_t - 0.1
            parts.append(block((hx - 0.006, hd, hz - 0.06), (hx + 0.006, hd + 0.022, hz + 0.06), handle, "metal"))
    else:  # an open metal frame with a low shelf
        frame = pick(rng, METALS[2:4])
        parts = [*legs(-hw, hw, -hd, hd, 0.0, stand_h - top_t, 0.035, frame, "metal"),
                 block((-hw, -hd, stand_h - top_t), (hw, hd, stand_h), frame, "metal"),
                 block((-hw + 0.035, -hd + 0.035, 0.12), (hw - 0.035, hd - 0.035, 0.14), shade(wood, 0.9), "wood")]
    # The tank: trim rails, the water volume, and a hood whose top is the receptacle.
    z0, z1 = stand_h, stand_h + tank_h
    hood_h = rng.uniform(0.03, 0.08)
    trim_h = 0.025
    w = 0.006  # how far the water's face lies inside the trim
    parts += [block((-hw, -hd, z0), (hw, hd, z0 + trim_h), trim, "plastic"),
              block((-hw + w, -hd + w, z0 + trim_h), (hw - w, hd - w, z1 - trim_h), water, "glass"),
              block((-hw, -hd, z1 - trim_h), (hw, hd, z1), trim, "plastic")]
    hood_lo, hood_hi = (-hw, -hd, z1), (hw, hd, z1 + hood_h)
    parts.append(block(hood_lo, hood_hi, trim, "plastic"))
    for sx in (-1.0, 1.0):  # front corner strips of the frame
        x0, x1 = sorted((sx * hw, sx * (hw - 0.012)))
        parts.append(block((x0, hd - 0.012, z0 + trim_h), (x1, hd, z1 - trim_h), trim, "plastic", collision="none"))
    # What shows through the front glass: sand, plants, a rock, fish (thin, just proud of the water).
    yf = hd - w
    sand_top = z0 + trim_h + rng.uniform(0.04, 0.08)
    parts.append(block((-hw + w, yf, z0 + trim_h), (hw - w, yf + 0.002, sand_top), sand, "plain", collision="none"))
    for sx in (-1.0, 1.0):  # and through the ends
        x0, x1 = sorted((sx * (hw - w), sx * (hw - w + 0.002)))
        parts.append(block((x0, -hd + w, z0 + trim_h), (x1, hd - w, sand_top), sand, "plain", collision="none"))
    inner = hw - 0.03
    for _ in range(int(rng.integers(2, 5))):
        pw = rng.uniform(0.015, 0.04)
        px = rng.uniform(-inner + pw, inner - pw)
        ph = (z1 - trim_h - sand_top) * rng.uniform(0.35, 0.8)
        parts.append(block((px - pw, yf + 0.001, sand_top - 0.01), (px + pw, yf + 0.003, sand_top + ph),
                           pick(rng, FOLIAGE, jitter=0.12), "plain", collision="none"))
    if rng.random() < 0.6:
        rw = rng.uniform(0.04, 0.08)
        rx = rng.uniform(-inner + rw, inner - rw)
        parts.append(block((rx - rw, yf + 0.001, sand_top - 0.01), (rx + rw, yf + 0.0035, sand_top + rw * 0.7),
                           pick(rng, BUILDING_STONES[:2]), "plain", collision="none"))
    for _ in range(int(rng.integers(1, 4))):
        fx = rng.uniform(-inner + 0.04, inner - 0.04)
        fz = rng.uniform(sand_top + 0.04, z1 - trim_h - 0.05)
        fl, fh = rng.uniform(0.025, 0.045), rng.uniform(0.01, 0.018)
        parts.append(block((fx - fl, yf + 0.002, fz - fh), (fx + fl, yf + 0.004, fz + fh), pick(rng, FISH),
                           "plain", collision="none"))
    litres = (width - 2 * w) * (depth - 2 * w) * (tank_h - 2 * trim_h) * 1000.0
    return finish("aquarium", parts, receptacles=[top_receptacle("top", hood_lo, hood_hi)],
                  names=["aquarium", "fish tank"], rooms=["living_room", "office"], placement="wall",
                  front_clearance=0.5, mass=float(0.9 * litres + rng.uniform(25, 45)))


def make_floor_fan(rng: np.random.Generator) -> AssetModel:
    if rng.random() < 0.3:  # a metal fan: chrome, brass or black
        body, material = pick(rng, METALS[1:2] + METALS[3:], jitter=0.03), "metal"
    else:
        body, material = pick(rng, DARK_PLASTICS, jitter=0.03), "plastic"
    accent = shade(body, 0.75) if body[0] > 0.3 else shade(body, 2.5)
    parts: list[Part]
    if rng.random() < 0.35:  # a tower fan: an oval column with a grille down its front
        height = rng.uniform(0.75, 1.1)
        rx, ry = rng.uniform(0.07, 0.1), rng.uniform(0.06, 0.08)
        base_r = rng.uniform(0.12, 0.16)
        parts = [rod(0.0, 0.0, 0.0, 0.035, base_r, accent, material, segments=12),
                 lathe([(1.0, 0.035), (1.0, height - 0.02), (0.85, height)], body, material, segments=12,
                       scale_xy=(rx, ry)),
                 block((-rx * 0.45, ry * 0.8, 0.15), (rx * 0.45, ry + 0.004, height - 0.1), (0.1, 0.1, 0.11, 1.0),
                       "plastic", collision="none"),
                 block((-rx * 0.5, -ry * 0.4, height - 0.01), (rx * 0.5, ry * 0.5, height + 0.004), accent,
                       "plastic", collision="none")]
        names = ["fan", "floor fan", "electric fan", "tower fan"]
    else:  # a pedestal fan: base, pole, motor, blades behind a guard ring
        hub_z = rng.uniform(0.85, 1.15)
        radius = rng.uniform(0.17, 0.24)
        blade_c = pick(rng, ((0.85, 0.9, 0.95), (0.55, 0.7, 0.85), (0.2, 0.2, 0.22), (0.9, 0.9, 0.88)))
        if rng.random() < 0.6:
            base_r = rng.uniform(0.14, 0.2)
            parts = [rod(0.0, 0.0, 0.0, 0.04, base_r, body, material, segments=10, radius_top=base_r * 0.85)]
        else:  # a cross base of two feet
            arm = rng.uniform(0.16, 0.22)
            parts = [block((-arm, -0.025, 0.0), (arm, 0.025, 0.035), body, material),
                     block((-0.025, -arm, 0.0), (0.025, arm, 0.035), body, material)]
        motor_y0, motor_y1 = -rng.uniform(0.1, 0.16), 0.04
        gy = motor_y1 + 0.04  # the blades' plane
        parts += [rod(0.0, 0.0, 0.03, hub_z * 0.6, 0.02, body, material, segments=8),
                  rod(0.0, 0.0, hub_z * 0.6, hub_z - 0.05, 0.013, METALS[1] + (1.0,), "metal", segments=6),
                  block((-0.03, -0.03, hub_z - 0.07), (0.03, 0.03, hub_z - 0.03), body, material),
                  _bar_y(0.0, motor_y0, motor_y1, hub_z, rng.uniform(0.055, 0.075), body, material, segments=10,
                         radius_end=0.045),
                  _bar_y(0.0, motor_y1, gy + 0.02, hub_z, 0.01, accent, "metal", segments=6, collision="none"),
                  _ring_y(0.0, hub_z, gy + 0.03, gy + 0.045, radius + 0.005, radius - 0.012, accent, material,
                          segments=10, collision="hull"),
                  _bar_y(0.0, gy + 0.03, gy + 0.05, hub_z, 0.045, body, material, segments=8, collision="none")]
        n_blades = int(rng.integers(3, 6))
        start = rng.uniform(0, 2 * np.pi)
        bw = rng.uniform(0.05, 0.09)
        for k in range(n_blades):
            blade = block((-bw / 2, gy - 0.004, hub_z + 0.03), (bw / 2, gy + 0.004, hub_z + radius - 0.025), blade_c,
                          "plastic", collision="none")
            parts.append(transformed(blade, rotate_y=start + 2 * np.pi * k / n_blades, pivot=(0.0, gy, hub_z)))
        for k in range(int(rng.integers(2, 4))):  # grille spokes across the front ring
            spoke = block((-0.004, gy + 0.036, hub_z - radius + 0.008), (0.004, gy + 0.04, hub_z + radius - 0.008),
                          accent, material, collision="none")
            parts.append(transformed(spoke, rotate_y=np.pi * k / 3 + 0.3, pivot=(0.0, gy, hub_z)))
        names = ["fan", "floor fan", "electric fan", "pedestal fan"]
    return finish("floor_fan", parts, names=names, rooms=["bedroom", "living_room", "office"], placement="corner",
                  front_clearance=0.3, mass=float(rng.uniform(3, 7)))


def make_radiator(rng: np.random.Generator) -> AssetModel:
    width = rng.uniform(0.5, 1.6)
    paint = pick(rng, RADIATORS, jitter=0.02)
    valve = pick(rng, METALS[:2] + ((0.95, 0.95, 0.94),))
    hw = width / 2
    recs: list[Receptacle] = []
    if rng.random() < 0.6:  # panel radiator: one or two panels hung off the wall
        panel_h = rng.uniform(0.3, 0.6)
        lift = rng.uniform(0.1, 0.18)
        panels = int(rng.integers(1, 3))
        pt, gap = 0.026, 0.05  # panel, and the convector fins between two panels
        stand_off = 0.035  # brackets hold it off the wall
        y = stand_off
        parts = []
        for _ in range(panels):
            parts.append(block((-hw, y, lift), (hw, y + pt, lift + panel_h), paint, "metal"))
            y += pt + gap
        front = y - gap
        top_z = lift + panel_h
        for sx in (-0.7, 0.7):  # wall brackets
            parts.append(block((sx * hw - 0.02, 0.0, top_z - 0.1), (sx * hw + 0.02, stand_off, top_z - 0.06),
                               shade(paint, 0.8), "metal"))
        # Horizontal ribs pressed into the front panel.
        for z in np.linspace(lift + 0.05, top_z - 0.05, 3):
            parts.append(block((-hw + 0.02, front, z - 0.004), (hw - 0.02, front + 0.003, z + 0.004),
                               shade(paint, 0.93), "metal", collision="none"))
        if panels == 2:  # a grille across the top of both panels
            grille = (-hw, stand_off, top_z), (hw, front, top_z + 0.012)
            parts.append(block(*grille, shade(paint, 0.96), "metal"))
            recs.append(top_receptacle("top", *grille, inset=0.005))
            top_z += 0.012
        if rng.random() < 0.35:  # a shelf above it
            shelf_d = rng.uniform(0.16, 0.2)
            shelf_c, shelf_m = (pick(rng, WOODS), "wood") if rng.random() < 0.6 else (paint, "metal")
            lo, hi = (-hw - 0.05, 0.0, top_z + 0.06), (hw + 0.05, shelf_d, top_z + 0.085)
            parts.append(block(lo, hi, shelf_c, shelf_m))
            for sx in (-0.8, 0.8):
                parts.append(block((sx * hw - 0.015, 0.0, top_z + 0.012), (sx * hw + 0.015, 0.03, top_z + 0.06),
                                   shelf_c, shelf_m))
            recs = [top_receptacle("shelf", lo, hi)]
        # Pipes down to the floor at both ends, a valve with a head on one of them.
        py = stand_off + pt / 2
        side = 1.0 if rng.random() < 0.5 else -1.0
        for sx in (-1.0, 1.0):
            px = sx * (hw - 0.04)
            parts.append(rod(px, py, 0.0, lift, 0.009, valve, "metal", segments=6))
        vx = side * (hw - 0.04)
        parts += [rod(vx, py, lift * 0.4, lift * 0.75, 0.016, valve, "metal", segments=8),
                  _bar_y(vx, py, py + 0.07, lift * 0.55, 0.022, WHITE, "plastic", segments=8, collision="none")]
        mass = 25.0 * panels * width * panel_h
    else:  # column radiator: vertical sections between headers, on feet
        height = rng.uniform(0.4, 0.9)
        depth = rng.uniform(0.07, 0.16)
        pitch = max(0.05, width / 20)
        n = max(4, int(width / pitch))
        cw = pitch * rng.uniform(0.55, 0.75)
        foot = rng.uniform(0.06, 0.12)
        parts = [block((-hw, depth * 0.25, foot + 0.02), (hw, depth * 0.75, foot + 0.06), paint, "metal"),
                 block((-hw, depth * 0.25, height - 0.06), (hw, depth * 0.75, height - 0.02), paint, "metal")]
        for x in np.linspace(-hw + cw / 2, hw - cw / 2, n):
            parts.append(block((x - cw / 2, 0.0, foot), (x + cw / 2, depth, height), paint, "metal"))
        for sx in (-1.0, 1.0):
            x0, x1 = sorted((sx * (hw - 0.06), sx * (hw - 0.06 - cw)))
            parts.append(block((x0, 0.0, 0.0), (x1, depth, foot), shade(paint, 0.7), "metal"))
        side = 1.0 if rng.random() < 0.5 else -1.0
        vz = foot + 0.04
        v0, v1 = sorted((side * hw, side * (hw + 0.06)))
        parts.append(_bar_x(v0, v1, depth / 2, vz, 0.012, valve, "metal", segments=6))
        mass = 45.0 * width * height * depth / 0.06
    return finish("radiator", parts, receptacles=recs, names=["radiator", "heating radiator", "heater"],
                  rooms=["bedroom", "living_room", "bathroom", "hallway", "office", "kitchen", "dining_room"],
                  placement="wall", front_clearance=0.2, mass=float(mass))


def _umbrella(rng: np.random.Generator, length: float) -> list[Part]:
    """A closed umbrella standing on its tip at the origin: canopy, shaft and handle."""
    cloth = pick(rng, FABRICS + ((0.1, 0.1, 0.11), (0.7, 0.15, 0.15)), jitter=0.08)
    wide = rng.uniform(0.035, 0.05)
    canopy_top = length * rng.uniform(0.74, 0.82)
    handle = pick(rng, WOODS[:3] + ((0.1, 0.1, 0.11),), jitter=0.05)
    parts = [lathe([(0.006, 0.0), (wide, length * 0.45), (0.012, canopy_top)], cloth, "fabric", segments=6),
             rod(0.0, 0.0, canopy_top, length, 0.006, METALS[2] + (1.0,), "metal", segments=6, collision="none")]
    if rng.random() < 0.6:  # a crook
        parts += [block((-0.012, -0.012, length), (0.085, 0.012, length + 0.025), handle, "wood", collision="none"),
                  block((0.06, -0.012, length - 0.07), (0.085, 0.012, length), handle, "wood", collision="none")]
    else:
        parts.append(rod(0.0, 0.0, length, length + 0.11, 0.016, handle, "wood", segments=6, collision="none"))
    return parts


def _lean(part: Part, spin: float, lean: float, toward: float, offset) -> Part:
    """``part`` (standing at the origin) turned by ``spin`` about z, leaned by ``lean`` radians
    toward the horizontal direction ``toward``, and moved by ``offset``."""
    cs, ss = np.cos(spin), np.sin(spin)
    rz = np.array([[cs, -ss, 0.0], [ss, cs, 0.0], [0.0, 0.0, 1.0]])
    # The lean: a rotation about the horizontal axis perpendicular to ``toward``.
    ax = np.array([-np.sin(toward), np.cos(toward), 0.0])
    c, s = np.cos(lean), np.sin(lean)
    k = np.array([[0.0, -ax[2], ax[1]], [ax[2], 0.0, -ax[0]], [-ax[1], ax[0], 0.0]])
    rl = np.eye(3) + s * k + (1 - c) * (k @ k)
    mat = np.eye(4)
    mat[:3, :3] = rl @ rz
    mat[:3, 3] = np.asarray(offset, dtype=np.float64)
    return part.transformed(mat)


def make_umbrella_stand(rng: np.random.Generator) -> AssetModel:
    height = rng.uniform(0.4, 0.55)
    if rng.random() < 0.5:
        color, material = pick(rng, CERAMICS), "ceramic"
    else:
        color, material = pick(rng, METALS + WOODS[:2]), "metal"
    if rng.random() < 0.55:  # round: a turned vessel, maybe waisted
        r = rng.uniform(0.1, 0.16)
        mid = r * rng.uniform(0.8, 1.05)
        parts = [lathe([(r * 0.9, 0.0), (mid, height * 0.5), (r, height), (r - 0.01, height), (mid - 0.01, height * 0.5),
                        (r * 0.9 - 0.01, 0.02)], color, material, segments=10)]
        reach = min(mid, r) - 0.04
    else:  # square: four walls on a base
        if material == "ceramic" and rng.random() < 0.6:
            color, material = pick(rng, WOODS), "wood"
        s, t = rng.uniform(0.1, 0.14), 0.03
        parts = [block((-s, -s, 0.0), (s, s, 0.02), shade(color, 0.8), material),
                 block((-s, -s, 0.02), (-s + t, s, height), color, material),
                 block((s - t, -s, 0.02), (s, s, height), color, material),
                 block((-s + t, -s, 0.02), (s - t, -s + t, height), color, material),
                 block((-s + t, s - t, 0.02), (s - t, s, height), color, material)]
        reach = s - 0.04
    n = int(rng.integers(1, 4))
    start = rng.uniform(0, 2 * np.pi)
    for k in range(n):
        a = start + 2 * np.pi * k / n + rng.uniform(-0.4, 0.4)
        lean = rng.uniform(0.06, 0.14)
        # The tip sits off centre away from the lean, so the shaft crosses the rim inside the mouth.
        tip = (-np.cos(a) * reach * 0.6, -np.sin(a) * reach * 0.6, 0.02)
        umb = _umbrella(rng, rng.uniform(0.8, 0.92))
        spin = rng.uniform(-np.pi, np.pi)
        parts += [_lean(p, spin, lean, a, tip) for p in umb]
    return finish("umbrella_stand", parts, names=["umbrella stand", "umbrella holder", "umbrella bin"],
                  rooms=["hallway"], placement="corner", front_clearance=0.3, mass=float(rng.uniform(2, 7)))


def make_grandfather_clock(rng: np.random.Generator) -> AssetModel:
    width, depth, height = rng.uniform(0.42, 0.58), rng.uniform(0.25, 0.33), rng.uniform(1.85, 2.15)
    wood = pick(rng, WOODS[:6])
    trim = shade(wood, 0.8)
    brass = pick(rng, METALS[4:] + METALS[1:2], jitter=0.03)
    face_c = pick(rng, ((0.96, 0.95, 0.9), (0.93, 0.9, 0.8), (0.97, 0.97, 0.97)), jitter=0.02)
    hw, hd = width / 2, depth / 2
    base_h, hood_h = rng.uniform(0.28, 0.4), rng.uniform(0.42, 0.52)
    crown = rng.choice(["flat", "stepped", "finials"])
    crown_h = 0.05 if crown == "flat" else rng.uniform(0.1, 0.16)
    hood_top = height - crown_h
    trunk_top = hood_top - hood_h
    tw, td = hw * rng.uniform(0.72, 0.85), hd * 0.85  # the trunk, narrower than base and hood
    foot = rng.uniform(0.03, 0.06) if rng.random() < 0.5 else 0.0
    parts = [block((-hw, -hd, foot), (hw, hd, base_h), wood, "wood"),
             block((-hw - 0.012, -hd, base_h - 0.03), (hw + 0.012, hd + 0.012, base_h), trim, "wood"),
             block((-tw, -td, base_h), (tw, td, trunk_top), wood, "wood"),
             block((-hw - 0.012, -hd, trunk_top), (hw + 0.012, hd + 0.012, trunk_top + 0.03), trim, "wood"),
             block((-hw, -hd, trunk_top + 0.03), (hw, hd, hood_top), wood, "wood")]
    if foot:  # bracket feet: a front and a back rail
        parts += [block((-hw, -hd, 0.0), (hw, -hd + 0.05, foot), trim, "wood"),
                  block((-hw, hd - 0.05, 0.0), (hw, hd, foot), trim, "wood")]
    recs = []
    if crown == "flat":
        lo, hi = (-hw - 0.02, -hd, hood_top), (hw + 0.02, hd + 0.02, height)
        parts.append(block(lo, hi, trim, "wood"))
        recs.append(top_receptacle("top", lo, hi))
    else:  # a stepped pediment, maybe with finials
        steps = np.linspace(hood_top, height, 4)
        for i in range(3):
            s = hw + 0.02 - i * (hw * 0.3)
            parts.append(block((-s, -hd, steps[i]), (s, hd + 0.02 - 0.01 * i, steps[i + 1]), trim, "wood"))
        if crown == "finials":
            for x in (-hw + 0.01, 0.0, hw - 0.01):
                z = height if x == 0.0 else steps[1]
                parts.append(rod(x, 0.0, z, z + 0.07, 0.018, brass, "metal", segments=5, radius_top=0.006))
    # The dial on the hood's front: a square brass plate, a white face, markers and two hands.
    fy = hd
    dial_r = min(hw - 0.05, (hood_h - 0.03) / 2 - 0.04)
    cz = trunk_top + 0.03 + (hood_h - 0.03) / 2
    plate = dial_r + 0.02
    parts += [block((-plate, fy, cz - plate), (plate, fy + 0.008, cz + plate), brass, "metal", collision="none"),
              _bar_y(0.0, fy + 0.008, fy + 0.014, cz, dial_r, face_c, "plain", segments=12, collision="none")]
    ink = (0.08, 0.08, 0.08, 1.0)
    for k in range(4):
        mark = block((-0.006, fy + 0.014, cz + dial_r - 0.035), (0.006, fy + 0.017, cz + dial_r - 0.01), ink,
                     "plain", collision="none")
        parts.append(transformed(mark, rotate_y=k * np.pi / 2, pivot=(0.0, fy, cz)))
    minute = rng.uniform(0, 2 * np.pi)
    hour = rng.uniform(0, 2 * np.pi)
    for angle, length, y in ((hour, dial_r * 0.55, fy + 0.017), (minute, dial_r * 0.85, fy + 0.02)):
        hand = block((-0.005, y, cz - 0.01), (0.005, y + 0.003, cz + length), ink, "metal", collision="none")
        # Clockwise as seen from the front (+y) is a negative turn about y.
        parts.append(transformed(hand, rotate_y=-angle, pivot=(0.0, y, cz)))
    # The trunk's door with its pendulum window.
    win_w = tw - rng.uniform(0.05, 0.08)
    win_top = trunk_top - rng.uniform(0.06, 0.1)
    win_bot = base_h + (trunk_top - base_h) * rng.uniform(0.05, 0.35)
    parts.append(block((-win_w, td, win_bot), (win_w, td + 0.004, win_top), (0.12, 0.12, 0.13, 1.0), "glass",
                       collision="none"))
    bob_z = win_bot + rng.uniform(0.12, 0.2)
    parts += [block((-0.006, td + 0.004, bob_z), (0.006, td + 0.007, win_top - 0.02), brass, "metal",
                    collision="none"),
              _bar_y(0.0, td + 0.004, td + 0.01, bob_z, min(0.07, win_w - 0.02), brass, "metal", segments=8,
                     collision="none")]
    return finish("grandfather_clock", parts, receptacles=recs,
                  names=["grandfather clock", "longcase clock", "tall clock", "floor clock"],
                  rooms=["living_room", "hallway", "dining_room"], placement="wall", front_clearance=0.4,
                  mass=float(rng.uniform(40, 90)))


FACTORIES = {
    "shower": make_shower,
    "vanity": make_vanity,
    "towel_rack": make_towel_rack,
    "laundry_hamper": make_laundry_hamper,
    "standing_mirror": make_standing_mirror,
    "fireplace": make_fireplace,
    "aquarium": make_aquarium,
    "floor_fan": make_floor_fan,
    "radiator": make_radiator,
    "umbrella_stand": make_umbrella_stand,
    "grandfather_clock": make_grandfather_clock,
}

register_builtins(FACTORIES)
