"""Named house specs: ``generate_house(seed, "OneRoom")``."""

from __future__ import annotations

from legent_gym.world.generation.conditions import HouseSpec

#: Preset name -> spec. OneRoom and TwoRoom are the houses of the LEGENT paper.
PRESETS: dict[str, HouseSpec] = {
    "OneRoom": HouseSpec(name="OneRoom", rooms=["bedroom"]),
    "TwoRoom": HouseSpec(name="TwoRoom", rooms=["bedroom", "living_room"]),
    "FourRoom": HouseSpec(name="FourRoom", rooms=["bedroom", "living_room", "kitchen", "bathroom"]),
    "Apartment": HouseSpec(name="Apartment", room_options=[
        ["bedroom", "living_room", "kitchen", "bathroom", "hallway", "office"],
        ["bedroom", "living_room", "kitchen", "bathroom", "dining_room", "office"],
        ["bedroom", "living_room", "kitchen", "bathroom", "hallway", "dining_room"],
        ["bedroom", "bedroom", "living_room", "kitchen", "bathroom", "hallway"],
        ["bedroom", "living_room", "kitchen", "bathroom", "office"],
        ["bedroom", "living_room", "kitchen", "bathroom", "dining_room"],
    ]),
}


def _key(name: str) -> str:
    return name.lower().replace("_", "").replace("-", "").replace(" ", "")


def preset(name: str) -> HouseSpec | None:
    """The preset called ``name`` (case, spaces, '-' and '_' ignored), else None."""
    for key, spec in PRESETS.items():
        if _key(key) == _key(name):
            return spec
    return None
