"""Built-in small objects of kitchens and dining rooms: food, vessels and cookware (pickupable, parametric, seeded, low-poly; registered on import).

The conventions are those of :mod:`legent_gym.world.assets.library.objects`.
"""

from __future__ import annotations

import numpy as np

from legent_gym.world.assets.library.common import (
    APPLIANCES,
    BRIGHT_PLASTICS,
    CERAMICS,
    DARK_PLASTICS,
    GLASSES,
    METALS,
    RGBA,
    WHITE,
    WOODS,
    block,
    flatten_bottom,
    lathe,
    pick,
    register_builtins,
    rod,
    shade,
    small_object,
    transformed,
)
from legent_gym.world.assets.model import AssetModel, Part, cylinder_part, mesh_part, sphere_part

KITCHEN = ["kitchen", "dining_room"]
#: Handles of cookware: black bakelite or plastic, and wood.
HANDLES = DARK_PLASTICS[:2] + WOODS[:2]



def _scaled(part: Part, sx: float, sy: float, sz: float) -> Part:
    """``part`` stretched about the origin."""
    return part.transformed(np.diag([sx, sy, sz, 1.0]))


def _bumpy(part: Part, rng: np.random.Generator, amount: float) -> Part:
    """``part`` with each vertex pushed in or out from its centre by up to ``amount`` (a fraction)."""
    c = part.vertices.mean(axis=0)
    f = 1.0 + rng.uniform(-amount, amount, size=(len(part.vertices), 1))
    return Part.exact(c + (part.vertices - c) * f, part.faces.copy(), part.rgba, part.collision,
                      material=part.material)


# ---------------------------------------------------------------------------------------
# Food.


def make_lemon(rng: np.random.Generator) -> AssetModel:
    r, length = rng.uniform(0.027, 0.032), rng.uniform(1.25, 1.4)
    color = pick(rng, ((0.98, 0.88, 0.2), (0.95, 0.8, 0.12), (0.9, 0.88, 0.3), (0.98, 0.92, 0.4)))
    # Lemons lie on their side: the long axis is horizontal, sliced flat like the round fruit.
    body = sphere_part((0, 0, 0.95 * r), r, color, scale=(length, 1.0, 0.95), material="food")
    body = flatten_bottom(body, 0.2 * 0.95 * r)
    tips = []
    for sx in (-1, 1):
        tip = cylinder_part((0, 0, 0), 0.25 * r, 0.012, shade(color, 0.9), segments=6, material="food",
                            radius_top=0.08 * r, collision="none")
        tips.append(transformed(tip, rotate_y=sx * np.pi / 2, offset=(sx * (length * r + 0.001), 0, 0.95 * r)))
    return small_object("lemon", [body, *tips], ["lemon"], 900.0, KITCHEN)


def make_potato(rng: np.random.Generator) -> AssetModel:
    r = rng.uniform(0.026, 0.034)
    sx, sz = rng.uniform(1.3, 1.7), rng.uniform(0.75, 0.9)
    color = pick(rng, ((0.72, 0.55, 0.35), (0.62, 0.45, 0.27), (0.8, 0.66, 0.45), (0.55, 0.27, 0.22)))
    body = sphere_part((0, 0, 0), r, color, scale=(sx, 1.0, sz), material="food")
    # Lumpy rather than an exact ellipsoid; flattened deeper than a fruit, as potatoes lie on a side.
    body = flatten_bottom(_bumpy(body, rng, 0.07), 0.3 * r * sz)
    return small_object("potato", [body], ["potato"], 1050.0, ["kitchen"])


BREAD_CRUSTS = ((0.78, 0.52, 0.26), (0.66, 0.4, 0.19), (0.86, 0.66, 0.4), (0.46, 0.3, 0.17))


def make_bread(rng: np.random.Generator) -> AssetModel:
    crust = pick(rng, BREAD_CRUSTS)
    length = rng.uniform(0.2, 0.3)
    if rng.random() < 0.5:
        # A tin loaf: a block with a domed top that overhangs it a little.
        w, h = rng.uniform(0.1, 0.13), rng.uniform(0.07, 0.09)
        dome = rng.uniform(0.025, 0.04)
        hl, hw = length / 2, w / 2
        top = cylinder_part((0, 0, 0), hw * 1.06, length, crust, segments=10, material="food")
        top = _scaled(transformed(top, rotate_y=np.pi / 2), 1.0, 1.0, dome / (hw * 1.06))
        parts = [block((-hl, -hw, 0.0), (hl, hw, h), shade(crust, 1.1), "food"),
                 transformed(top, offset=(0, 0, h))]
    else:
        # A round-ended farmhouse loaf: a squat ellipsoid with a flat bottom.
        w, h = rng.uniform(0.11, 0.16), rng.uniform(0.07, 0.1)
        rz = h / 1.4
        body = sphere_part((0, 0, 0), 1.0, crust, scale=(length / 2, w / 2, rz), material="food")
        parts = [flatten_bottom(body, 0.6 * rz)]
    return small_object("bread", parts, ["bread", "loaf", "loaf of bread"], 230.0, KITCHEN)


# ---------------------------------------------------------------------------------------
# Tableware and containers.


def make_wine_glass(rng: np.random.Generator) -> AssetModel:
    h = rng.uniform(0.17, 0.22)
    rb, foot = rng.uniform(0.036, 0.043), rng.uniform(0.031, 0.037)
    rim = rb * rng.uniform(0.78, 0.92)
    stem_top = h * rng.uniform(0.4, 0.48)
    widest = stem_top + 0.45 * (h - stem_top)
    wall, stem_r = 0.0025, 0.0035
    color = pick(rng, GLASSES[:1] + GLASSES[3:], jitter=0.04)
    # Foot, stem, bowl up to the rim and down the inside to a pole at the bottom of the bowl;
    # the outside of the bowl's base follows the inside, so the glass stays thin there too.
    floor = stem_top + 0.008
    knee = 0.5 * rb
    knee_z = floor + (widest - floor) * knee / (rb - wall) - 0.004
    body = lathe([(foot, 0.0), (stem_r, 0.01), (stem_r, stem_top), (knee, knee_z), (rb, widest), (rim, h),
                  (rim - wall, h), (rb - wall, widest), (0.0, floor)], color, "glass", segments=9)
    return small_object("wine_glass", [body], ["wine glass", "glass", "wineglass"], 2500.0,
                  ["kitchen", "dining_room", "living_room"])


JAR_CONTENTS = ((0.85, 0.6, 0.15), (0.6, 0.1, 0.12), (0.45, 0.55, 0.2), (0.78, 0.86, 0.86), (0.5, 0.3, 0.15))


def make_jar(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.035, 0.05), rng.uniform(0.09, 0.17)
    if rng.random() < 0.6:
        # A glass jar (jam, honey, pickles) with a screw lid: the glass shows its contents.
        neck = r * rng.uniform(0.8, 0.92)
        lid_h = rng.uniform(0.012, 0.018)
        body = lathe([(r, 0.0), (r, 0.85 * (h - lid_h)), (neck, h - lid_h)], pick(rng, JAR_CONTENTS),
                     "glass")
        lid = rod(0, 0, h - lid_h - 0.003, h, neck + 0.003, pick(rng, METALS[:2] + BRIGHT_PLASTICS[:4]), "metal",
                  segments=10)
        return small_object("jar", [body, lid], ["jar", "glass jar"], 900.0, KITCHEN)
    # A ceramic storage canister: straight sides, a rounded shoulder, a shallow lid with a knob.
    color = pick(rng, CERAMICS)
    lid_h = rng.uniform(0.015, 0.022)
    hb = h - lid_h - 0.012
    body = lathe([(0.92 * r, 0.0), (r, 0.12 * hb), (r, 0.85 * hb), (0.86 * r, hb)], color, "ceramic")
    lid = rod(0, 0, hb - 0.003, hb + lid_h, 0.88 * r, shade(color, 0.92), "ceramic", segments=10,
              radius_top=0.7 * r)
    knob = block((-0.009, -0.009, hb + lid_h - 0.002), (0.009, 0.009, h), shade(color, 0.8), "ceramic")
    return small_object("jar", [body, lid, knob], ["jar", "ceramic jar", "canister"], 700.0, KITCHEN)


def make_teapot(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.065, 0.085), rng.uniform(0.1, 0.13)
    if rng.random() < 0.8:
        color, material = pick(rng, CERAMICS), "ceramic"
    else:
        color, material = pick(rng, METALS[:2] + METALS[4:]), "metal"
    # Belly, shoulder, then the lid as one dome on top.
    body = lathe([(0.62 * r, 0.0), (r, 0.4 * h), (0.82 * r, 0.82 * h), (0.5 * r, h), (0.15 * r, h + 0.015)],
                 color, material, segments=8)
    knob = block((-0.007, -0.007, h + 0.01), (0.007, 0.007, h + 0.026), shade(color, 0.85), material)
    # The spout leaves the lower belly and rises toward +x to about the height of the lid.
    length = rng.uniform(0.08, 0.1)
    spout = rod(0, 0, 0, length, 0.016, color, material, segments=6, radius_top=0.007)
    spout = transformed(spout, rotate_y=rng.uniform(0.6, 0.75), offset=(0.75 * r, 0, 0.35 * h))
    # A three-bar handle on the -x side, from the shoulder down to the belly.
    x_out, t, w = -(r + 0.035), 0.01, 0.007
    z0, z1 = 0.25 * h, 0.8 * h
    parts = [body, knob, spout,
             block((x_out, -w, z1 - t), (-0.82 * r + 0.004, w, z1), color, material),
             block((x_out, -w, z0), (x_out + t, w, z1 - t), color, material),
             block((x_out + t, -w, z0), (-0.95 * r + 0.004, w, z0 + t), color, material)]
    return small_object("teapot", parts, ["teapot", "tea pot"], 450.0, KITCHEN)


CARTON_PRINTS = BRIGHT_PLASTICS[:4] + ((0.1, 0.3, 0.65), (0.35, 0.6, 0.85))


def _gable(a: float, b: float, z0: float, z1: float, rgba: RGBA, material: str) -> Part:
    """A triangular prism (a gable roof) over the rectangle |x| <= a, |y| <= b, ridge along x at z1."""
    v = [(-a, -b, z0), (a, -b, z0), (a, b, z0), (-a, b, z0), (-a, 0.0, z1), (a, 0.0, z1)]
    f = [(0, 2, 1), (0, 3, 2), (0, 4, 3), (1, 2, 5), (0, 1, 5), (0, 5, 4), (3, 4, 5), (3, 5, 2)]
    return mesh_part(v, f, rgba, material=material)


def make_milk_carton(rng: np.random.Generator) -> AssetModel:
    w, h = rng.uniform(0.07, 0.095), rng.uniform(0.155, 0.195)
    gable, fin = 0.35 * w, rng.uniform(0.01, 0.015)
    carton = pick(rng, (WHITE[:3], (0.96, 0.94, 0.88)), jitter=0.02)
    brand = pick(rng, CARTON_PRINTS)
    a = w / 2
    parts = [block((-a, -a, 0.0), (a, a, h), carton, "paper"),
             _gable(a, a, h, h + gable, brand, "paper"),
             block((-a, -0.0015, h + gable - 0.003), (a, 0.0015, h + gable + fin), carton, "paper"),
             # The printed band around the front and the back.
             block((-a - 0.0005, -a - 0.0005, 0.45 * h), (a + 0.0005, a + 0.0005, 0.75 * h), brand, "paper",
                   collision="none")]
    # A full carton: milk, less the air in the gable.
    return small_object("milk_carton", parts, ["milk carton", "milk"], 950.0, KITCHEN)


# ---------------------------------------------------------------------------------------
# Cookware.


def make_kettle(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.07, 0.085), rng.uniform(0.19, 0.24)
    if rng.random() < 0.5:
        shell, material = pick(rng, METALS[:3]), "metal"
    else:
        shell, material = pick(rng, APPLIANCES[::2] + APPLIANCES[3:] + BRIGHT_PLASTICS[:2]), "plastic"
    trim = pick(rng, DARK_PLASTICS[:2])
    base_h = rng.uniform(0.015, 0.02)
    # The power base the kettle stands on.
    parts = [rod(0, 0, 0.0, base_h, r + 0.005, trim, "plastic")]
    if rng.random() < 0.5:
        top_r, low_r = 0.62 * r, r
        parts.append(lathe([(0.88 * r, base_h), (r, base_h + 0.35 * (h - base_h)),
                            (0.92 * r, base_h + 0.75 * (h - base_h)), (top_r, h)], shell, material, segments=8))
        parts.append(block((-0.012, -0.012, h), (0.012, 0.012, h + 0.012), trim, "plastic"))
    else:
        top_r, low_r = 0.82 * r, 0.95 * r
        parts.append(rod(0, 0, base_h, h, r, shell, material, radius_top=top_r))
        parts.append(rod(0, 0, h, h + 0.006, 0.75 * top_r, trim, "plastic", collision="none"))
    spout = block((0.0, -0.012, -0.012), (0.035, 0.012, 0.0), shell, material, collision="hull")
    parts.append(transformed(spout, rotate_y=-0.5, offset=(top_r - 0.01, 0, h - 0.008)))
    # A D-shaped handle on the -x side: from the rim, down, and back into the lower body.
    x_out, t, w = -(r + 0.04), 0.016, 0.012
    z0 = base_h + 0.25 * (h - base_h)
    parts += [block((x_out, -w, h - t), (-top_r + 0.01, w, h), trim, "plastic"),
              block((x_out, -w, z0), (x_out + t, w, h - t), trim, "plastic"),
              block((x_out + t, -w, z0), (-low_r + 0.01, w, z0 + t), trim, "plastic")]
    # An empty kettle: a thin shell, much lighter than its volume of plastic.
    return small_object("kettle", parts, ["kettle", "electric kettle"], 230.0, ["kitchen"])


POT_ENAMELS = ((0.75, 0.15, 0.12), (0.15, 0.3, 0.6), (0.9, 0.88, 0.82), (0.3, 0.45, 0.35))


def make_cooking_pot(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.08, 0.11), rng.uniform(0.08, 0.15)
    color = pick(rng, METALS[:3] + POT_ENAMELS)
    handle = pick(rng, HANDLES[:2] + METALS[:1])
    wall = 0.0025
    lidded = rng.random() < 0.6
    segments = 8 if lidded else 10
    parts = [lathe([(r, 0.0), (r, h), (r - wall, h), (r - wall, 0.004)], color, "metal", segments=segments)]
    if lidded:
        # A thin domed shell resting on the rim: underside first (a pole in the middle), then over the top.
        dome, lid_c = rng.uniform(0.015, 0.025), pick(rng, METALS[:2] + GLASSES[:1])
        parts.append(lathe([(0.0, h + dome), (r + 0.004, h), (r + 0.004, h + 0.003), (0.0, h + dome + 0.003)],
                           lid_c, "metal", segments=segments))
        parts.append(block((-0.015, -0.008, h + dome), (0.015, 0.008, h + dome + 0.018), handle, "plastic"))
    hz = h - rng.uniform(0.015, 0.03)
    for sx in (-1, 1):
        x0, x1 = sorted((sx * (r - 0.004), sx * (r + 0.035)))
        parts.append(block((x0, -0.025, hz - 0.012), (x1, 0.025, hz), handle, "plastic"))
    return small_object("cooking_pot", parts, ["pot", "cooking pot", "saucepan"], 5000.0, ["kitchen"])


def make_frying_pan(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.1, 0.14), rng.uniform(0.035, 0.055)
    rb = r * rng.uniform(0.75, 0.85)
    if rng.random() < 0.4:
        color, density = pick(rng, ((0.12, 0.12, 0.13),), jitter=0.03), 7200.0  # cast iron
        handle = color
    else:
        color, density = pick(rng, METALS[:3] + ((0.55, 0.2, 0.15), (0.2, 0.3, 0.45))), 2700.0  # aluminium
        handle = pick(rng, HANDLES)
    # A thick floor and walls: the pan outweighs its handle, so its centre of mass stays well inside the base.
    wall, floor = 0.004, 0.006
    body = lathe([(rb, 0.0), ((rb + r) / 2, 0.5 * h), (r, h), (r - wall, h), ((rb + r) / 2 - wall, 0.5 * h),
                  (rb - wall, floor)], color, "metal", segments=10)
    length, tilt = rng.uniform(0.16, 0.21), rng.uniform(0.12, 0.22)
    bar = block((0.0, -0.012, -0.011), (length, 0.012, 0.0), handle, "plastic" if handle != color else "metal",
                collision="hull")
    # Raised toward its end, starting just below the rim.
    bar = transformed(bar, rotate_y=-tilt, offset=(r - 0.01, 0, h - 0.004))
    rivet = block((r - 0.012, -0.016, h - 0.022), (r + 0.012, 0.016, h - 0.002), color, "metal")
    return small_object("frying_pan", [body, rivet, bar], ["pan", "frying pan", "skillet"], density, ["kitchen"])


CHOPPING_PLASTICS = (WHITE[:3], (0.3, 0.6, 0.3), (0.85, 0.25, 0.2), (0.25, 0.45, 0.75), (0.95, 0.85, 0.3))


def make_cutting_board(rng: np.random.Generator) -> AssetModel:
    if rng.random() < 0.65:
        color, material, density = pick(rng, WOODS[:5]), "wood", 680.0
        t = rng.uniform(0.016, 0.028)
    else:
        color, material, density = pick(rng, CHOPPING_PLASTICS), "plastic", 950.0
        t = rng.uniform(0.012, 0.018)
    length, w = rng.uniform(0.24, 0.4), rng.uniform(0.16, 0.28)
    shape = rng.random()
    if shape < 0.45:
        parts = [block((-length / 2, -w / 2, 0.0), (length / 2, w / 2, t), color, material)]
    elif shape < 0.75:
        # A paddle: a board with a handle tab at one end.
        tab = rng.uniform(0.06, 0.09)
        hl = (length - tab) / 2
        parts = [block((-hl, -w / 2, 0.0), (hl, w / 2, t), color, material),
                 block((hl - 0.005, -0.025, 0.0), (hl + tab, 0.025, t), color, material)]
    else:
        parts = [lathe([(length / 2, 0.0), (length / 2, t)], color, material, segments=12,
                       scale_xy=(1.0, w / length))]
    return small_object("cutting_board", parts, ["cutting board", "chopping board"], density, ["kitchen"])


FACTORIES = {
    "lemon": make_lemon,
    "potato": make_potato,
    "bread": make_bread,
    "wine_glass": make_wine_glass,
    "kettle": make_kettle,
    "cooking_pot": make_cooking_pot,
    "frying_pan": make_frying_pan,
    "cutting_board": make_cutting_board,
    "jar": make_jar,
    "teapot": make_teapot,
    "milk_carton": make_milk_carton,
}

register_builtins(FACTORIES)
