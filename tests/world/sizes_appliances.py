"""Size ranges of the built-in furniture of legent_gym/world/assets/library/appliances.py:
(min size, max size) of the bounding box (x, y, z), metres; and what tests/world/test_asset_library.py
checks of them besides."""

SIZES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "stove": ((0.5, 0.6, 0.85), (0.92, 0.75, 1.12)),
    "microwave": ((0.43, 0.32, 0.24), (0.61, 0.46, 0.35)),
    "dishwasher": ((0.43, 0.55, 0.8), (0.62, 0.68, 0.88)),
    "washing_machine": ((0.54, 0.5, 0.8), (0.62, 0.7, 0.88)),
    "dryer": ((0.54, 0.55, 0.82), (0.62, 0.7, 0.89)),
    "kitchen_island": ((1.2, 0.62, 0.86), (2.4, 1.1, 0.96)),
    "bar_stool": ((0.32, 0.32, 0.58), (0.5, 0.5, 1.12)),
    "trash_can": ((0.2, 0.2, 0.25), (0.45, 0.46, 0.8)),
    "pantry_cabinet": ((0.45, 0.4, 1.8), (1.05, 0.65, 2.31)),
    "coffee_machine": ((0.14, 0.25, 0.24), (0.36, 0.5, 0.48)),
    "toaster": ((0.25, 0.15, 0.16), (0.52, 0.33, 0.23)),
}
#: Moving links: the joint kind ("hinge" or "slide") of each articulated asset.
ARTICULATED: dict[str, str] = {"microwave": "hinge", "pantry_cabinet": "hinge"}
#: Assets that must offer a place to put things: how many receptacles at least.
EXPECTED_RECEPTACLES: dict[str, int] = {
    "stove": 1, "microwave": 1, "dishwasher": 1, "washing_machine": 1, "dryer": 1, "kitchen_island": 1,
    "pantry_cabinet": 4,
}
