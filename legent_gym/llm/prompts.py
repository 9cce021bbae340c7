"""The prompts legent_gym sends to LLMs, in one place and versioned.

:data:`SCENE_PLAN_PROMPT` (version :data:`SCENE_PLAN_PROMPT_VERSION`) asks a chat model to
write a :class:`~legent_gym.world.generation.plan.ScenePlan` for a description of a home
(:mod:`legent_gym.llm.scene_from_text` sends it). :data:`TASK_PROMPT` (version
:data:`TASK_PROMPT_VERSION`) asks for tasks in a house, given its object table
(:mod:`legent_gym.llm.task_generation` runs it). :data:`ANNOTATION_PROMPT` (version
:data:`ANNOTATION_PROMPT_VERSION`) asks a VLM what an asset shown in four views is
(:mod:`legent_gym.llm.annotation` sends it).
"""

from __future__ import annotations

from typing import Any

from legent_gym.tasks import TASKS
from legent_gym.world.generation.conditions import Catalog
from legent_gym.world.generation.roomtypes import ROOM_TYPES

SCENE_PLAN_PROMPT_VERSION = 1

SCENE_PLAN_PROMPT = """\
You design homes for a 3-D simulator. Write the plan of the home the user describes as one \
JSON object, with no text around it, in this form:

{{"version": 1, "name": "<short name>",
  "rooms": [{{"name": "<unique room name>", "type": "<room type>", "size": <floor area in m^2, 5 to 40>,
             "objects": [{{"name": "<unique in the room>", "asset": "<category>", "count": <1 to 6>,
                          "on": "<name of the object it stands on, or null>",
                          "relations": [{{"kind": "<relation>", "target": "<object name or null>"}}]}}]}}],
  "doors": [["<room name>", "<room name>"]]}}

Room types: {room_types}.
Asset categories (use these exact names): furniture: {furniture}; things that stand on \
furniture: {surface}; small objects (give them "on"): {small}.
Relations: "against_wall" and "middle" (no target); "near", "far", "facing", "in_front_of", \
"left_of", "right_of" (target: another object of the same room).
Rules: 1 to {max_rooms} rooms; doors link rooms that should open into each other; at most \
12 objects per room; every target and "on" names an object of the same room."""

#: Sent back when a reply is not a valid plan (legent_gym.llm.client adds the error itself).
SCENE_PLAN_USER = "Describe the home: {prompt}"


def scene_plan_messages(prompt: str, catalog: Any = None) -> list[dict[str, str]]:
    """The chat messages that ask for a plan of ``prompt`` (the library's categories listed)."""
    catalog = catalog or Catalog.from_registry()
    furniture = [c for c in catalog.categories if catalog.is_furniture(c) and catalog.describe(c).placement != "surface"]
    surface = [c for c in catalog.categories if catalog.is_furniture(c) and catalog.describe(c).placement == "surface"]
    small = [c for c in catalog.categories if catalog.is_small(c)]
    system = SCENE_PLAN_PROMPT.format(room_types=", ".join(ROOM_TYPES[t].name for t in ROOM_TYPES),
                                      furniture=", ".join(furniture), surface=", ".join(surface) or "(none)",
                                      small=", ".join(small), max_rooms=8)
    return [{"role": "system", "content": system}, {"role": "user", "content": SCENE_PLAN_USER.format(prompt=prompt)}]


# -- tasks for a scene -------------------------------------------------------------------

#: 2: the kinds, which objects may be picked up, and the code examples come from the
#: registered tasks (:data:`legent_gym.tasks.TASKS`: each task's ``kinds`` and ``code``).
TASK_PROMPT_VERSION = 2

TASK_PROMPT = """\
You write tasks for an embodied agent in a 3-D house, in the manner of LEGENT's task \
creator. A user stands in the house and speaks an instruction; the agent carries it out. \
The house's objects (id | name | x | y | z in metres | what it stands on | can be picked up):

{objects}

The agent stands at ({agent_x:.2f}, {agent_y:.2f}); the user at {user}.

Write {n} different tasks as one JSON object, with no text around it:

{{"tasks": [{{"kind": "<kind>", "instruction": "<what the user says>", "target": <object id or null>,
             "receptacle": <object id or null>, "code": "<the agent's intermediate code>"}}]}}

Kinds: {kinds}. Only objects that can be picked up may be the target of {fetching}.
Code is a sequence of calls: goto_user(), goto(id), find(id), target(id), interact(), \
grab(), put(), speak("..."), finish(). goto(id) walks to the object; target(id) aims at it; \
interact() grabs what is aimed at, or puts the held object where it aims. For example: \
{examples}. Use only the ids of the table."""

TASK_USER = "Write {n} tasks for this house."
#: The objects and the receptacle's name the code examples of :data:`TASK_PROMPT` use.
EXAMPLE_CODE_FIELDS = {"a": 7, "b": 3, "b_name": "table"}


def task_kinds_text() -> dict[str, str]:
    """The parts of :data:`TASK_PROMPT` read from the registered tasks: ``kinds`` (each
    kind of a tasks file and what it asks), ``fetching`` (the kinds whose target is picked
    up) and ``examples`` (each task's code, by its first kind)."""
    tasks = [task for task in TASKS.values() if task.kinds]
    quoted = [f'"{kind}"' for task in tasks if task.fetches_target() for kind in task.kinds]
    return {"kinds": ", ".join(f'"{kind}" ({text})' for task in tasks for kind, text in task.kinds.items()),
            "fetching": " or ".join(filter(None, (", ".join(quoted[:-1]), *quoted[-1:]))) or "no kind",
            "examples": "; ".join(f"{next(iter(task.kinds))}: {task.code.format(**EXAMPLE_CODE_FIELDS)}"
                                  for task in tasks if task.code)}


def task_messages(objects: str, agent_xy: tuple[float, float], user_xy: tuple[float, float] | None,
                  n: int) -> list[dict[str, str]]:
    """The chat messages that ask for ``n`` tasks in a house with this object table."""
    user = "nowhere (no user)" if user_xy is None else f"({user_xy[0]:.2f}, {user_xy[1]:.2f})"
    system = TASK_PROMPT.format(objects=objects, agent_x=agent_xy[0], agent_y=agent_xy[1], user=user, n=n,
                                **task_kinds_text())
    return [{"role": "system", "content": system}, {"role": "user", "content": TASK_USER.format(n=n)}]


# -- asset annotation ----------------------------------------------------------------------

ANNOTATION_PROMPT_VERSION = 1

ANNOTATION_PROMPT = """\
These are four views of one 3-D asset for a household simulator, from cameras 90 degrees \
apart around it (views 0, 1, 2, 3). Its bounding box is {x:.2f} x {y:.2f} x {z:.2f} m \
(width, depth, height). Describe it as one JSON object, with no text around it:

{{"name": "<what people call it, e.g. mug>", "category": "<one or two words, e.g. coffee_table>",
  "description": "<one sentence>", "pickable": <can a person pick it up with one hand: true/false>,
  "receptacle": <can things be put on it: true/false>, "on_floor": <true/false>,
  "on_wall": <true/false>, "on_object": <does it stand on furniture: true/false>,
  "materials": ["<material>", ...], "mass": <kilograms>, "front_view": <0-3: the view that shows its front>}}"""
