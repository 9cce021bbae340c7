"""Built-in small objects the agent can pick up: parametric, seeded, low-poly, registered on import.

Each factory takes the registry's generator and returns a pickupable :class:`AssetModel` in
the asset frame (footprint centred on the origin, resting on z = 0, front facing +y).
Objects are shaped to rest stably on a flat surface: round fruit is sliced flat underneath,
vessels have flat bottoms. Mass is the enclosed volume times a density typical of the
material, so bigger variants are heavier.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from legent_gym.world.assets.library.common import (
    BRIGHT_PLASTICS,
    CERAMICS,
    DARK_PLASTICS,
    GLASSES,
    METALS,
    RGBA,
    SCREEN,
    WHITE,
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
from legent_gym.world.assets.model import AssetModel, Part, cylinder_part, sphere_part

STEM: RGBA = (0.35, 0.24, 0.12, 1.0)
LEAF: RGBA = (0.25, 0.5, 0.2, 1.0)
KITCHEN = ["kitchen", "dining_room"]



# ---------------------------------------------------------------------------------------
# Food.


def _round_fruit(radius: float, squash: float, rgba: RGBA) -> Part:
    """An icosphere (80 triangles) squashed in z and sliced flat underneath."""
    body = sphere_part((0, 0, radius * squash), radius, rgba, scale=(1.0, 1.0, squash), material="food")
    # At one subdivision the lowest ring of six vertices is 0.19 radii above the pole: slicing
    # there leaves a flat hexagon about 1.1 radii across to stand on.
    return flatten_bottom(body, 0.2 * radius * squash)


def make_apple(rng: np.random.Generator) -> AssetModel:
    r = rng.uniform(0.035, 0.045)
    color = pick(rng, ((0.75, 0.1, 0.1), (0.55, 0.08, 0.1), (0.55, 0.75, 0.2), (0.9, 0.75, 0.25)))
    body = _round_fruit(r, 0.9, color)
    top = body.vertices[:, 2].max()
    parts = [body, block((-0.002, -0.002, top - 0.004), (0.002, 0.002, top + 0.012), STEM, "food",
                         collision="none")]
    return small_object("apple", parts, ["apple"], 800.0, KITCHEN)


def make_orange(rng: np.random.Generator) -> AssetModel:
    r = rng.uniform(0.035, 0.045)
    color = pick(rng, ((0.95, 0.55, 0.1), (0.93, 0.45, 0.05), (0.98, 0.62, 0.2)))
    body = _round_fruit(r, 0.95, color)
    top = body.vertices[:, 2].max()
    parts = [body, block((-0.004, -0.004, top - 0.003), (0.004, 0.004, top + 0.002), LEAF, "food",
                         collision="none")]
    return small_object("orange", parts, ["orange"], 850.0, KITCHEN)


def make_tomato(rng: np.random.Generator) -> AssetModel:
    r = rng.uniform(0.025, 0.04)
    color = pick(rng, ((0.85, 0.12, 0.08), (0.9, 0.25, 0.1), (0.95, 0.6, 0.1)))
    body = _round_fruit(r, 0.8, color)
    top = body.vertices[:, 2].max()
    parts = [body, block((-0.3 * r, -0.3 * r, top - 0.003), (0.3 * r, 0.3 * r, top + 0.002), LEAF, "food",
                         collision="none")]
    return small_object("tomato", parts, ["tomato"], 950.0, KITCHEN)


def make_pear(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.03, 0.04), rng.uniform(0.09, 0.12)
    color = pick(rng, ((0.75, 0.8, 0.3), (0.85, 0.75, 0.3), (0.6, 0.45, 0.2), (0.5, 0.7, 0.25)))
    body = lathe([(0.55 * r, 0.0), (r, 0.25 * h), (0.92 * r, 0.45 * h), (0.55 * r, 0.7 * h),
                  (0.35 * r, 0.9 * h), (0.12 * r, h)], color, "food")
    stem = block((-0.002, -0.002, h - 0.003), (0.002, 0.002, h + 0.015), STEM, "food", collision="none")
    return small_object("pear", [body, stem], ["pear"], 900.0, KITCHEN)


def _bent_tube(radii: list[float], arc_radius: float, arc_angle: float, rgba: RGBA, material: str) -> Part:
    """A hexagonal tube bent along an arc in the xy plane, each section resting on z = 0."""
    cos_p, sin_p = _TUBE_RING
    thetas = np.linspace(-arc_angle / 2, arc_angle / 2, len(radii))
    centre, normal = [], []
    for theta, r in zip(thetas, radii):
        centre.append([arc_radius * np.sin(theta), arc_radius * (np.cos(theta) - 1), r * np.sin(np.pi / 3)])
        normal.append([np.sin(theta), np.cos(theta), 0.0])
    # Every section's ring at once: element by element the arithmetic of
    # centre + r * (cos(p) * normal + (0, 0, sin(p))), one vertex at a time.
    ring = np.zeros((len(_TUBE_RING[0]), 3))
    ring[:, 2] = sin_p
    rings = (np.array(centre)[:, None, :] + np.array(radii, dtype=np.float64)[:, None, None]
             * (cos_p[None, :, None] * np.array(normal)[:, None, :] + ring[None, :, :]))
    # The caps' centre vertices: the mean of the first and of the last ring.
    verts = np.concatenate([rings.reshape(-1, 3), [np.mean(rings[0], axis=0), np.mean(rings[-1], axis=0)]])
    return Part(verts, _tube_faces(len(radii)).copy(), rgba, "hull", material=material)


#: cos and sin of a hexagonal tube's six directions (a flat side at the bottom, 240..300
#: degrees), each by its own call, as the tube's vertices were once computed one by one.
_TUBE_RING = tuple(np.array([f(p) for p in np.arange(6) * 2 * np.pi / 6]) for f in (np.cos, np.sin))


@lru_cache(maxsize=16)
def _tube_faces(sections: int) -> np.ndarray:
    """Faces of a hexagonal tube of ``sections`` rings, capped at both ends (read-only)."""
    sides = 6
    faces = []
    for i in range(sections - 1):
        for k in range(sides):
            a, b = i * sides + k, i * sides + (k + 1) % sides
            faces += [[a, b + sides, a + sides], [a, b, b + sides]]
    for ring, flip in ((0, True), (sections - 1, False)):
        hub = sections * sides + (0 if flip else 1)  # the cap's centre vertex
        for k in range(sides):
            tri = [hub, ring * sides + k, ring * sides + (k + 1) % sides]
            faces.append(tri[::-1] if flip else tri)
    out = np.array(faces, dtype=np.int32)
    out.flags.writeable = False
    return out


def make_banana(rng: np.random.Generator) -> AssetModel:
    length, r = rng.uniform(0.17, 0.22), rng.uniform(0.018, 0.022)
    color = pick(rng, ((0.95, 0.82, 0.2), (0.9, 0.85, 0.3), (0.75, 0.8, 0.25)))
    bend = rng.uniform(0.6, 0.9)  # radians of arc
    arc_radius = length / bend
    body = _bent_tube([0.3 * r, 0.8 * r, r, r, 0.8 * r, 0.35 * r], arc_radius, bend, color, "food")
    tip = body.vertices[:6].mean(axis=0)
    stem = block(tip - (0.012, 0.004, 0.004), tip + (0.0, 0.004, 0.004), STEM, "food", collision="none")
    return small_object("banana", [body, stem], ["banana"], 900.0, KITCHEN)


# ---------------------------------------------------------------------------------------
# Kitchenware.


def _vessel(radius_bottom: float, radius_top: float, height: float, wall: float, floor: float,
            rgba: RGBA, material: str, *, bulge: float = 0.0, segments: int = 10) -> Part:
    """An open vessel (cup, mug, bowl): outside up, over the rim, down the inside to its floor."""
    mid_r = (radius_bottom + radius_top) / 2 + bulge
    return lathe([(radius_bottom, 0.0), (mid_r, 0.55 * height), (radius_top, height),
                  (radius_top - wall, height), (mid_r - wall, 0.55 * height),
                  (max(radius_bottom - wall, 0.005), floor)], rgba, material, segments=segments)


def make_mug(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.038, 0.045), rng.uniform(0.08, 0.1)
    color = pick(rng, CERAMICS)
    body = _vessel(r, r, h, 0.005, 0.008, color, "ceramic")
    # A square handle of three bars on the +x side.
    x0, x1, t = r - 0.004, r + 0.028, 0.008
    z0, z1 = 0.25 * h, 0.85 * h
    parts = [body,
             block((x0, -0.006, z1 - t), (x1, 0.006, z1), color, "ceramic"),
             block((x1 - t, -0.006, z0), (x1, 0.006, z1 - t), color, "ceramic"),
             block((x0, -0.006, z0), (x1 - t, 0.006, z0 + t), color, "ceramic")]
    return small_object("mug", parts, ["mug", "coffee mug"], 2000.0, ["kitchen", "office", "living_room"])


#: Cup kinds: (palette, wall thickness m, density kg/m^3 of the wall, names).
CUP_KINDS = {
    "paper": (((0.95, 0.95, 0.93), (0.85, 0.75, 0.6), (0.7, 0.2, 0.15)), 0.002, 400.0, ["cup", "paper cup"]),
    "glass": (GLASSES[:1] + GLASSES[3:], 0.004, 2500.0, ["cup", "glass", "drinking glass"]),
    "plastic": (BRIGHT_PLASTICS, 0.002, 1000.0, ["cup", "plastic cup"]),
}


def make_cup(rng: np.random.Generator) -> AssetModel:
    kind = list(CUP_KINDS)[int(rng.integers(len(CUP_KINDS)))]
    palette, wall, density, names = CUP_KINDS[kind]
    rb, h = rng.uniform(0.026, 0.033), rng.uniform(0.08, 0.12)
    rt = rb + rng.uniform(0.008, 0.014)
    body = _vessel(rb, rt, h, wall, 0.006, pick(rng, palette), kind)
    return small_object("cup", [body], names, density, ["kitchen", "dining_room", "office"])


def make_bowl(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.065, 0.09), rng.uniform(0.045, 0.075)
    color, material = (pick(rng, CERAMICS), "ceramic") if rng.random() < 0.75 else (pick(rng, BRIGHT_PLASTICS), "plastic")
    body = _vessel(0.5 * r, r, h, 0.005, 0.007, color, material, bulge=0.15 * r)
    return small_object("bowl", [body], ["bowl"], 2000.0 if material == "ceramic" else 1000.0, KITCHEN)


def make_plate(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.1, 0.14), rng.uniform(0.015, 0.025)
    color = pick(rng, CERAMICS)
    body = lathe([(0.6 * r, 0.0), (r, h), (r - 0.012, h), (0.6 * r, 0.006)], color, "ceramic", segments=12)
    return small_object("plate", [body], ["plate", "dish"], 2200.0, KITCHEN)


def make_bottle(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.03, 0.042), rng.uniform(0.19, 0.27)
    neck = rng.uniform(0.012, 0.016)
    glass = rng.random() < 0.5
    color = pick(rng, GLASSES) if glass else pick(rng, ((0.7, 0.85, 0.95), (0.8, 0.9, 0.9)))
    cap = pick(rng, BRIGHT_PLASTICS + METALS[:1])
    shoulder = rng.uniform(0.55, 0.7) * h
    body = lathe([(r, 0.0), (r, shoulder), (neck, shoulder + 0.25 * (h - shoulder) + 0.03), (neck, h - 0.012)],
                 color, "glass" if glass else "plastic")
    parts = [body, rod(0, 0, h - 0.014, h, neck + 0.002, cap, "plastic")]
    names = ["bottle", "glass bottle"] if glass else ["bottle", "water bottle", "plastic bottle"]
    # A full bottle: about the density of water, less the air above the liquid.
    return small_object("bottle", parts, names, 950.0, ["kitchen", "dining_room", "office"])


def make_cola_can(rng: np.random.Generator) -> AssetModel:
    r, h = rng.uniform(0.032, 0.034), rng.uniform(0.112, 0.124)
    color = pick(rng, ((0.8, 0.05, 0.07), (0.65, 0.04, 0.06), (0.1, 0.1, 0.1), (0.75, 0.75, 0.78)), jitter=0.03)
    metal = pick(rng, METALS[:2], jitter=0.02)
    parts = [lathe([(0.85 * r, 0.0), (r, 0.01), (r, h - 0.012), (0.85 * r, h)], color, "metal"),
             cylinder_part((0, 0, h * 0.62), r + 0.0005, 0.012, WHITE, segments=10, collision="none",
                           material="metal"),
             rod(0, 0, h - 0.001, h + 0.001, 0.75 * r, metal, "metal", collision="none")]
    return small_object("cola_can", parts, ["cola", "cola can", "soda can", "can"], 850.0,
                  ["kitchen", "living_room", "dining_room"])


# ---------------------------------------------------------------------------------------
# Things around the house.


def make_book(rng: np.random.Generator) -> AssetModel:
    w, length, t = rng.uniform(0.13, 0.21), rng.uniform(0.19, 0.28), rng.uniform(0.015, 0.05)
    cover = pick(rng, BRIGHT_PLASTICS + ((0.15, 0.2, 0.35), (0.1, 0.3, 0.2), (0.35, 0.1, 0.1), (0.1, 0.1, 0.1)))
    pages = (0.95, 0.93, 0.86, 1.0)
    c, hw, hl = 0.003, w / 2, length / 2
    parts = [block((-hw, -hl, 0.0), (hw, hl, c), cover, "paper"),
             block((-hw, -hl, t - c), (hw, hl, t), cover, "paper"),
             block((-hw, -hl, c), (-hw + c, hl, t - c), cover, "paper"),
             block((-hw + c, -hl + c, c), (hw - c, hl - c, t - c), pages, "paper")]
    return small_object("book", parts, ["book"], 700.0, ["living_room", "bedroom", "office"])


def make_vase(rng: np.random.Generator) -> AssetModel:
    r = rng.uniform(0.05, 0.09)
    h = r * rng.uniform(2.2, 3.5)
    color, material = (pick(rng, CERAMICS), "ceramic") if rng.random() < 0.7 else (pick(rng, GLASSES), "glass")
    lip, wall = r * rng.uniform(0.5, 0.75), 0.006
    body = lathe([(0.7 * r, 0.0), (r, 0.35 * h), (0.55 * r, 0.85 * h), (lip, h), (lip - wall, h),
                  (0.55 * r - wall, 0.85 * h), (0.55 * r - wall, 0.6 * h)], color, material)
    # The lathe is solid below the neck; count the body as a thick shell.
    return small_object("vase", [body], ["vase"], 450.0, ["living_room", "dining_room", "bedroom", "hallway"])


def make_laptop(rng: np.random.Generator) -> AssetModel:
    w, d = rng.uniform(0.3, 0.38), rng.uniform(0.21, 0.26)
    base_t, lid_t = rng.uniform(0.014, 0.02), 0.006
    shell = pick(rng, ((0.75, 0.76, 0.78), (0.3, 0.31, 0.33), (0.1, 0.1, 0.11), (0.85, 0.75, 0.65)), jitter=0.03)
    tilt = rng.uniform(0.15, 0.4)  # lid leaning back from vertical, radians
    hw, hd = w / 2, d / 2
    lid_h = d - 0.01
    lid = [block((-hw, 0.0, 0.0), (hw, lid_t, lid_h), shell, "metal", collision="hull"),
           block((-hw + 0.01, lid_t, 0.01), (hw - 0.01, lid_t + 0.001, lid_h - 0.01), SCREEN, "glass",
                 collision="none")]
    lid = [transformed(p, rotate_x=tilt, offset=(0.0, -hd, base_t)) for p in lid]
    parts = [block((-hw, -hd, 0.0), (hw, hd, base_t), shell, "metal"),
             block((-hw + 0.02, -hd + 0.02, base_t), (hw - 0.02, -hd + 0.02 + 0.45 * d, base_t + 0.001),
                   shade(shell, 0.3), "plastic", collision="none"),
             block((-0.05, hd - 0.09, base_t), (0.05, hd - 0.02, base_t + 0.0005), shade(shell, 0.8), "plastic",
                   collision="none"),
             *lid]
    return small_object("laptop", parts, ["laptop", "laptop computer", "computer"], 1100.0,
                  ["office", "bedroom", "living_room"])


def make_remote(rng: np.random.Generator) -> AssetModel:
    w, length, t = rng.uniform(0.04, 0.055), rng.uniform(0.15, 0.21), rng.uniform(0.018, 0.025)
    body = pick(rng, DARK_PLASTICS)
    keys = shade(body, 0.5) if body[0] > 0.5 else (0.6, 0.6, 0.62, 1.0)
    hw, hl = w / 2, length / 2
    parts = [block((-hw, -hl, 0.0), (hw, hl, t), body, "plastic"),
             block((-0.006, hl - 0.025, t), (0.006, hl - 0.013, t + 0.002), (0.8, 0.1, 0.1, 1.0), "plastic",
                   collision="none"),
             block((-hw + 0.008, -hl + 0.02, t), (hw - 0.008, 0.3 * hl, t + 0.002), keys, "plastic",
                   collision="none")]
    return small_object("remote", parts, ["remote", "remote control", "tv remote"], 900.0,
                  ["living_room", "bedroom"])


def make_phone(rng: np.random.Generator) -> AssetModel:
    w, length, t = rng.uniform(0.068, 0.078), rng.uniform(0.14, 0.165), rng.uniform(0.0075, 0.0095)
    case = pick(rng, DARK_PLASTICS + BRIGHT_PLASTICS[:3])
    hw, hl = w / 2, length / 2
    parts = [block((-hw, -hl, 0.0), (hw, hl, t), case, "plastic"),
             block((-hw + 0.003, -hl + 0.004, t), (hw - 0.003, hl - 0.004, t + 0.0005), SCREEN, "glass",
                   collision="none")]
    return small_object("phone", parts, ["phone", "cell phone", "mobile phone", "smartphone"], 1900.0,
                  ["living_room", "bedroom", "office"])


def _toy_car(rng: np.random.Generator) -> list[Part]:
    length, w = rng.uniform(0.1, 0.16), rng.uniform(0.05, 0.07)
    wheel_r = rng.uniform(0.012, 0.017)
    paint = pick(rng, BRIGHT_PLASTICS)
    hl, hw = length / 2, w / 2
    body_top = wheel_r * 0.6 + rng.uniform(0.02, 0.03)
    parts = [block((-hw, -hl, wheel_r * 0.6), (hw, hl, body_top), paint, "plastic"),
             block((-hw + 0.006, -0.35 * length, body_top), (hw - 0.006, 0.15 * length, body_top + 0.5 * w),
                   shade(paint, 0.8), "plastic")]
    for x in (-hw - 0.004, hw + 0.004):
        for y in (-hl + 1.3 * wheel_r, hl - 1.3 * wheel_r):
            wheel = cylinder_part((x, y, wheel_r), wheel_r, 0.01, (0.1, 0.1, 0.1, 1.0), segments=8,
                                  material="plastic")
            parts.append(transformed(wheel, rotate_y=np.pi / 2, pivot=(x, y, wheel_r)))
    return parts


def _teddy(rng: np.random.Generator) -> list[Part]:
    r = rng.uniform(0.04, 0.06)
    fur = pick(rng, ((0.6, 0.42, 0.25), (0.8, 0.65, 0.45), (0.92, 0.9, 0.85), (0.45, 0.3, 0.2)))
    body_h = 2.0 * r
    head_r = 0.75 * r
    head_z = body_h + 0.8 * head_r
    parts = [lathe([(0.75 * r, 0.0), (r, 0.4 * body_h), (0.55 * r, body_h)], fur, "fabric", segments=8),
             sphere_part((0, 0, head_z), head_r, fur, material="fabric")]
    for sx in (-1, 1):
        x = sx * 0.7 * head_r
        parts.append(block((x - 0.3 * head_r, -0.15 * head_r, head_z + 0.5 * head_r),
                           (x + 0.3 * head_r, 0.15 * head_r, head_z + 1.05 * head_r), shade(fur, 0.8), "fabric"))
    return parts


def make_toy(rng: np.random.Generator) -> AssetModel:
    if rng.random() < 0.5:
        return small_object("toy", _toy_car(rng), ["toy", "toy car", "car"], 350.0, ["bedroom", "living_room"])
    return small_object("toy", _teddy(rng), ["toy", "teddy bear", "teddy", "stuffed animal"], 150.0,
                  ["bedroom", "living_room"])


FACTORIES = {
    "apple": make_apple,
    "orange": make_orange,
    "banana": make_banana,
    "pear": make_pear,
    "tomato": make_tomato,
    "cola_can": make_cola_can,
    "mug": make_mug,
    "cup": make_cup,
    "bowl": make_bowl,
    "plate": make_plate,
    "bottle": make_bottle,
    "book": make_book,
    "vase": make_vase,
    "laptop": make_laptop,
    "remote": make_remote,
    "phone": make_phone,
    "toy": make_toy,
}

register_builtins(FACTORIES)
