"""Size ranges of the built-in furniture of legent_gym/world/assets/library/bath_decor.py:
(min size, max size) of the bounding box (x, y, z), metres; and what tests/world/test_asset_library.py
checks of them besides."""

SIZES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "shower": ((0.78, 0.78, 1.85), (1.02, 1.02, 2.25)),
    "vanity": ((0.6, 0.45, 0.8), (1.22, 0.6, 1.25)),
    "towel_rack": ((0.48, 0.25, 0.78), (0.9, 0.45, 1.15)),
    "laundry_hamper": ((0.3, 0.28, 0.48), (0.62, 0.58, 0.8)),
    "standing_mirror": ((0.38, 0.1, 1.25), (0.85, 0.6, 2.0)),
    "fireplace": ((1.0, 0.45, 0.95), (1.8, 0.9, 1.35)),
    "aquarium": ((0.6, 0.3, 0.9), (1.45, 0.55, 1.5)),
    "floor_fan": ((0.22, 0.22, 0.75), (0.55, 0.5, 1.45)),
    "radiator": ((0.5, 0.05, 0.38), (1.75, 0.22, 0.92)),
    "umbrella_stand": ((0.18, 0.18, 0.75), (0.5, 0.5, 1.1)),
    "grandfather_clock": ((0.42, 0.25, 1.85), (0.64, 0.4, 2.25)),
}
#: Moving links: the joint kind ("hinge" or "slide") of each articulated asset.
ARTICULATED: dict[str, str] = {"vanity": "hinge"}
#: Assets that must offer a place to put things: how many receptacles at least.
EXPECTED_RECEPTACLES: dict[str, int] = {"vanity": 1, "fireplace": 1, "aquarium": 1}
