"""Size ranges of the built-in small objects of legent_gym/world/assets/library/decor.py:
(min size, max size) of the bounding box (x, y, z), metres."""

SIZES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "candle": ((0.045, 0.045, 0.06), (0.12, 0.12, 0.37)),
    "picture_frame": ((0.1, 0.04, 0.1), (0.3, 0.13, 0.3)),
    "alarm_clock": ((0.07, 0.03, 0.045), (0.16, 0.09, 0.15)),
    "desk_lamp": ((0.14, 0.14, 0.22), (0.3, 0.3, 0.5)),
    "pillow": ((0.26, 0.26, 0.07), (0.58, 0.58, 0.2)),
    "basket": ((0.15, 0.12, 0.09), (0.42, 0.42, 0.42)),
    "cardboard_box": ((0.15, 0.09, 0.08), (0.48, 0.42, 0.32)),
    "potted_plant": ((0.08, 0.08, 0.12), (0.25, 0.25, 0.42)),
    "figurine": ((0.03, 0.03, 0.04), (0.16, 0.16, 0.3)),
    "game_controller": ((0.1, 0.04, 0.012), (0.18, 0.12, 0.05)),
    "tissue_box": ((0.1, 0.1, 0.06), (0.28, 0.15, 0.22)),
}
