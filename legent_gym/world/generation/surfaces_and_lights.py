"""Looks of a generated house: floor and wall surfaces per room type, and ceiling lights.

(How a built world is drawn, its style preset and domain randomisation, is
:mod:`legent_gym.world.styles`.)
"""

from __future__ import annotations

import numpy as np

from legent_gym.world.geometry import points_in_polygon, polygon_centroid
from legent_gym.world.scene import Light, Surface

#: Room type -> floor (material, rgb) choices.
FLOORS: dict[str, list[tuple[str, tuple[float, float, float]]]] = {
    "bedroom": [("wood", (0.62, 0.48, 0.33)), ("wood", (0.74, 0.6, 0.44)), ("carpet", (0.56, 0.52, 0.48)),
                ("carpet", (0.45, 0.5, 0.58))],
    "living_room": [("wood", (0.55, 0.4, 0.27)), ("wood", (0.72, 0.58, 0.42)), ("wood", (0.42, 0.3, 0.2)),
                    ("carpet", (0.6, 0.56, 0.5))],
    "kitchen": [("tile", (0.86, 0.85, 0.82)), ("tile", (0.6, 0.62, 0.65)), ("stone", (0.5, 0.48, 0.45)),
                ("tile", (0.78, 0.72, 0.62))],
    "bathroom": [("tile", (0.9, 0.9, 0.9)), ("tile", (0.62, 0.7, 0.76)), ("tile", (0.55, 0.55, 0.58))],
    "dining_room": [("wood", (0.6, 0.45, 0.3)), ("wood", (0.48, 0.35, 0.24)), ("stone", (0.7, 0.68, 0.64))],
    "office": [("carpet", (0.45, 0.47, 0.5)), ("wood", (0.66, 0.52, 0.36)), ("carpet", (0.5, 0.44, 0.4))],
    "hallway": [("wood", (0.58, 0.44, 0.3)), ("stone", (0.66, 0.64, 0.6)), ("tile", (0.74, 0.72, 0.68))],
}
#: Room type -> wall (material, rgb) choices.
WALLS: dict[str, list[tuple[str, tuple[float, float, float]]]] = {
    "bedroom": [("paint", (0.9, 0.88, 0.84)), ("paint", (0.78, 0.84, 0.9)), ("paint", (0.9, 0.82, 0.8)),
                ("paint", (0.84, 0.88, 0.8))],
    "living_room": [("paint", (0.92, 0.9, 0.86)), ("paint", (0.86, 0.82, 0.74)), ("paint", (0.8, 0.84, 0.86)),
                    ("wallpaper", (0.84, 0.8, 0.72))],
    "kitchen": [("paint", (0.95, 0.95, 0.92)), ("tile", (0.9, 0.92, 0.9)), ("paint", (0.92, 0.88, 0.76))],
    "bathroom": [("tile", (0.94, 0.95, 0.96)), ("tile", (0.8, 0.88, 0.9)), ("paint", (0.9, 0.92, 0.88))],
    "dining_room": [("paint", (0.9, 0.86, 0.78)), ("wallpaper", (0.8, 0.76, 0.7)), ("paint", (0.86, 0.9, 0.86))],
    "office": [("paint", (0.88, 0.88, 0.86)), ("paint", (0.76, 0.8, 0.84)), ("paint", (0.82, 0.86, 0.78))],
    "hallway": [("paint", (0.92, 0.9, 0.86)), ("paint", (0.86, 0.86, 0.84))],
}
DEFAULT = [("plain", (0.8, 0.8, 0.8))]


def _surface(choices, rng: np.random.Generator) -> Surface:
    material, rgb = choices[int(rng.integers(len(choices)))]
    jitter = rng.uniform(-0.03, 0.03, 3)
    r, g, b = (round(float(np.clip(c + j, 0.0, 1.0)), 3) for c, j in zip(rgb, jitter))
    return Surface(material=material, rgba=(r, g, b, 1.0))


def room_surfaces(rtype: str, rng: np.random.Generator) -> tuple[Surface, Surface]:
    """(floor, wall) surfaces for a room of type ``rtype``."""
    return _surface(FLOORS.get(rtype, DEFAULT), rng), _surface(WALLS.get(rtype, DEFAULT), rng)


def ceiling_light(point: tuple[float, float], wall_height: float) -> Light:
    """One warm light under the ceiling."""
    return Light(position=(round(point[0], 4), round(point[1], 4), round(wall_height - 0.2, 4)),
                 diffuse=(0.55, 0.53, 0.5), cast_shadow=False)


def light_point(polygon: list[tuple[float, float]]) -> tuple[float, float]:
    """A point inside the room for its light: the centroid, or for an L-shape whose centroid
    falls outside, the centre of its larger arm."""
    p = np.asarray(polygon, dtype=np.float64)
    c = polygon_centroid(p)
    if points_in_polygon(c[None, :], p)[0]:
        return float(c[0]), float(c[1])
    # Fall back to the midpoint between the two vertices nearest the centroid (inside an L).
    best = None
    for i in range(len(p)):
        for j in range(i + 1, len(p)):
            m = (p[i] + p[j]) / 2
            if points_in_polygon(m[None, :], p)[0]:
                d = float(np.hypot(*(m - c)))
                if best is None or d < best[0]:
                    best = (d, m)
    m = best[1] if best else p.mean(axis=0)
    return float(m[0]), float(m[1])
