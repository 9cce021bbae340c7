"""Size ranges of the built-in fittings of legent_gym/world/assets/library/fittings.py:
(min size, max size) of the bounding box (x, y, z), metres, as a variant is made (the
generator stretches rugs, wall cabinets and curtains to where they go)."""

SIZES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "shelved_book": ((0.015, 0.13, 0.15), (0.06, 0.245, 0.3)),
    "rug": ((1.4, 0.9, 0.006), (2.6, 1.8, 0.014)),
    "wall_cabinet": ((0.5, 0.3, 0.55), (1.0, 0.385, 0.8)),
    "range_hood": ((0.6, 0.42, 0.2), (0.9, 0.5, 0.9)),
    "curtain": ((0.38, 0.03, 1.31), (0.58, 0.06, 1.72)),
    "cushion": ((0.34, 0.1, 0.32), (0.52, 0.16, 0.5)),
}
