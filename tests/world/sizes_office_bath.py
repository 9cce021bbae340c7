"""Size ranges of the built-in small objects of legent_gym/world/assets/library/office_bath.py:
(min size, max size) of the bounding box (x, y, z), metres."""

SIZES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "pen": ((0.12, 0.009, 0.008), (0.17, 0.018, 0.018)),
    "notebook": ((0.08, 0.11, 0.004), (0.23, 0.32, 0.03)),
    "stapler": ((0.12, 0.03, 0.035), (0.2, 0.055, 0.07)),
    "scissors": ((0.11, 0.04, 0.004), (0.22, 0.08, 0.012)),
    "keyboard": ((0.27, 0.1, 0.015), (0.48, 0.17, 0.04)),
    "computer_mouse": ((0.05, 0.085, 0.028), (0.075, 0.13, 0.048)),
    "tablet": ((0.12, 0.17, 0.005), (0.22, 0.3, 0.015)),
    "soap": ((0.07, 0.045, 0.018), (0.15, 0.12, 0.055)),
    "shampoo": ((0.04, 0.025, 0.15), (0.085, 0.075, 0.27)),
    "towel": ((0.2, 0.13, 0.015), (0.36, 0.26, 0.07)),
    "toilet_paper": ((0.09, 0.085, 0.09), (0.125, 0.125, 0.12)),
}
