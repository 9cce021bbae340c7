"""Scene plans and their solver: a versioned JSON description of a house (what an LLM
writes, or a person) and a deterministic search that builds a validated scene from it.

A plan (:class:`ScenePlan`, ``version`` :data:`PLAN_VERSION`) lists rooms (type, rough
size in m^2, objects), the pairs of rooms that must share a door, and per room the objects
(an asset category or any name for one, a count, ``on``: the object it stands on) with
relations to other objects of the room: ``near``, ``far``, ``against_wall``, ``middle``,
``facing``, ``in_front_of``, ``left_of``, ``right_of`` (``on`` is "on top of").

:func:`solve_plan` builds the house with the generator's parts: a floor plan grown on the
grid with the rooms' sizes (the plan whose requested doors can be made is kept), doors
(a spanning tree, then the requested pairs), windows, then per room a depth-first search
over candidate poses (wall, corner and free-floor poses, and poses beside, ahead of and
against the wall next to each relation's target), best soft score first (one point per
relation met, partial credit by distance), under hard constraints (inside the room, no
overlap, door squares and front zones clear, the room walkable between its doors with every
piece in reach). The search first looks for a layout meeting every relation (forward
checking, backtracking); the first :data:`STRICT_ATTEMPTS` houses are given up when a room
has none, later ones keep the best soft score instead. Surface furniture (a tv) and small
objects go on the receptacles of what they are ``on`` (else on any surface of the room); a
piece that planned small objects stand on gets an asset with surfaces most of their models
fit. The
finished scene passes :func:`~legent_gym.world.generation.validate.check_house`.

Nothing is silently ignored: a name that is no asset category is mapped to the nearest
one (``SolveReport.mapped``) or dropped (``SolveReport.warnings``); an object that fits
nowhere, a door that cannot be made and every relation not met in the result are listed in
``SolveReport.unmet`` with what was measured.

The modules (every name above is re-exported here): :mod:`~legent_gym.world.generation.plan.schema`,
the plan's pydantic models, the relations' thresholds and the solver's report;
:mod:`~legent_gym.world.generation.plan.solver`, :func:`solve_plan` and what it measures.
"""

from legent_gym.world.generation.plan.schema import (
    FACING_ANGLE,
    FAR_DISTANCE,
    NEAR_GAP,
    PLAN_VERSION,
    SIDE_ANGLE,
    WALL_CONTACT,
    PlannedObject,
    PlannedRoom,
    Relation,
    ScenePlan,
    SolvedScene,
    SolveReport,
    load_plan,
)
from legent_gym.world.generation.plan.solver import nearest_category, relation_scores, solve_plan

__all__ = ["FACING_ANGLE", "FAR_DISTANCE", "NEAR_GAP", "PLAN_VERSION", "SIDE_ANGLE", "WALL_CONTACT", "PlannedObject",
           "PlannedRoom", "Relation", "ScenePlan", "SolveReport", "SolvedScene", "load_plan", "nearest_category",
           "relation_scores", "solve_plan"]
