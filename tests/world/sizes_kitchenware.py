"""Size ranges of the built-in small objects of legent_gym/world/assets/library/kitchenware.py:
(min size, max size) of the bounding box (x, y, z), metres."""

SIZES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "lemon": ((0.07, 0.045, 0.04), (0.11, 0.075, 0.07)),
    "potato": ((0.06, 0.04, 0.03), (0.14, 0.085, 0.07)),
    "bread": ((0.18, 0.09, 0.06), (0.35, 0.18, 0.14)),
    "wine_glass": ((0.06, 0.06, 0.15), (0.1, 0.1, 0.24)),
    "kettle": ((0.17, 0.13, 0.18), (0.28, 0.22, 0.3)),
    "cooking_pot": ((0.2, 0.15, 0.07), (0.36, 0.28, 0.22)),
    "frying_pan": ((0.3, 0.18, 0.03), (0.55, 0.32, 0.12)),
    "cutting_board": ((0.2, 0.15, 0.01), (0.45, 0.3, 0.03)),
    "jar": ((0.06, 0.06, 0.08), (0.13, 0.13, 0.22)),
    "teapot": ((0.18, 0.11, 0.1), (0.3, 0.2, 0.2)),
    "milk_carton": ((0.07, 0.07, 0.19), (0.1, 0.1, 0.26)),
}
