"""Procedural houses: floor plans grown on a grid, doors, furniture, small objects, spawns.

``generate_house(seed, spec=None, **conditions)`` returns a validated
:class:`~legent_gym.world.scene.Scene`; the same arguments always give the same JSON.
``generate_house_with_grid`` returns its navigation grid too, for less than building one;
``GENERATOR_VERSION`` changes whenever a seed gives another house.
Presets (``PRESETS``): OneRoom (a bedroom), TwoRoom (bedroom + living room), FourRoom
(bedroom, living room, kitchen, bathroom), Apartment (5-6 rooms with an office, a dining
room or a hallway). :func:`check_house` lists what is wrong with any scene.
``plan``: scene plans (versioned JSON: rooms, doors, objects, relations) and
:func:`~legent_gym.world.generation.plan.solve_plan`, which builds a scene from one.
"""

from legent_gym.world.generation.conditions import CONDITION_NAMES, GenerationError, HouseSpec
from legent_gym.world.generation.house import (
           GENERATOR_VERSION,
           generate_house,
           generate_house_with_grid,
)
from legent_gym.world.generation.presets import PRESETS
from legent_gym.world.generation.roomtypes import ROOM_TYPES, parse_rooms
from legent_gym.world.generation.validate import check_house

__all__ = ["CONDITION_NAMES", "GENERATOR_VERSION", "GenerationError", "HouseSpec", "PRESETS", "ROOM_TYPES", "check_house",
           "generate_house", "generate_house_with_grid", "parse_rooms"]
