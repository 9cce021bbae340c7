"""Size ranges of the built-in furniture of legent_gym/world/assets/library/living.py:
(min size, max size) of the bounding box (x, y, z), metres; and what tests/world/test_asset_library.py
checks of them besides."""

SIZES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "ottoman": ((0.4, 0.4, 0.35), (1.0, 0.65, 0.5)),
    "bench": ((0.8, 0.3, 0.4), (1.6, 0.46, 0.52)),
    "stool": ((0.28, 0.28, 0.4), (0.48, 0.48, 0.52)),
    "office_chair": ((0.54, 0.6, 0.85), (0.7, 0.82, 1.32)),
    "filing_cabinet": ((0.38, 0.42, 0.58), (0.95, 0.7, 1.45)),
    "storage_cabinet": ((0.4, 0.35, 0.8), (1.05, 0.55, 1.9)),
    "shoe_rack": ((0.6, 0.26, 0.2), (1.0, 0.36, 0.9)),
    "coat_rack": ((0.28, 0.28, 1.7), (0.55, 0.55, 1.96)),
    "sideboard": ((1.2, 0.4, 0.7), (2.05, 0.53, 0.9)),
    "console_table": ((0.8, 0.25, 0.75), (1.4, 0.43, 0.85)),
    "piano": ((1.42, 0.55, 1.0), (1.58, 0.67, 1.33)),
    "chest": ((0.7, 0.4, 0.42), (1.26, 0.66, 0.61)),
}
#: Moving links: the joint kind ("hinge" or "slide") of each articulated asset, or the kinds
#: of one whose variants have both (each kind on some of them).
ARTICULATED: dict[str, str | tuple[str, ...]] = {"filing_cabinet": "slide", "storage_cabinet": "hinge",
                                                 "sideboard": ("hinge", "slide")}
#: Articulated assets some of whose variants have nothing that moves.
SOMETIMES_STATIC: set[str] = set()
#: Assets that must offer a place to put things: how many receptacles at least.
EXPECTED_RECEPTACLES: dict[str, int] = {
    "ottoman": 1, "bench": 1, "stool": 1, "filing_cabinet": 3, "storage_cabinet": 2, "shoe_rack": 2,
    "sideboard": 2, "console_table": 1, "piano": 1, "chest": 1,
}
