"""The paper's six task templates (Table 2): ComeHere, GoTo, PickUp, BringMe, WhereIs, PutOn.

Success rules (LEGENT's where it had one):

* ComeHere: the agent is within 2.0 m (horizontal) of the user, checked after every action.
* GoTo(A): A is within reach of the agent (horizontally, to the nearest point of A's
  footprint) and visible in its view.
* PickUp(A): the agent holds A.
* BringMe(A): the agent holds A within 2.0 m of the user.
* WhereIs(A): the agent's speech names A's receptacle (its name or a synonym, a
  lower-cased substring match as in LEGENT); any speech ends the episode.
* PutOn(A, B): A rests on B (not held, on one of B's surfaces, at rest).

Goals are drawn only among those the task expert can complete within the paper's
25-action cap (:mod:`legent_gym.tasks.feasibility`: somewhere to stand to see or act on
the objects, and an estimated plan of at most ``PLAN_BUDGET`` actions).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from legent_gym.tasks.base import Evaluation, Task, TaskContext, TaskInstance
from legent_gym.tasks.feasibility import PLAN_BUDGET, Leg, stand_leg, user_leg
from legent_gym.world.assets import registry
from legent_gym.world.generation.small_objects import PLAUSIBLE

COME_HERE_DISTANCE = 2.0


def _said(ctx: TaskContext, names: list[str]) -> bool:
    return any(name in text.lower() for text in ctx.speech for name in names)


def _to_user(ctx: TaskContext) -> float:
    """Geodesic metres left until the agent is within ComeHere's distance of the user."""
    return max(ctx.geodesic_to(ctx.user.xy) - COME_HERE_DISTANCE, 0.0)


def _object_distance(ctx: TaskContext, object_id: int) -> float:
    return ctx.distance_to_object(object_id)


def _draw(options: list, rng, achievable):
    """A uniformly drawn option that passes ``achievable`` (checked lazily, in the drawn
    order, so only the drawn goal pays for the check), or None."""
    for i in rng.permutation(len(options)):
        if achievable(options[int(i)]):
            return options[int(i)]
    return None


def _fits(*legs: Leg | None, interactions: int = 0) -> bool:
    """Every walk exists, and with the interactions the expert's plan stays within budget."""
    total = interactions
    for leg in legs:
        if leg is None:
            return False
        total += leg.actions
    return total <= PLAN_BUDGET


def _rests_on(ctx: TaskContext, item: int, host: int) -> bool:
    """The item is not held, at rest, and over one of the host's surfaces at its height."""
    if ctx.agent.state.held == item:
        return False
    world = ctx.world
    pos = world.object_position(item)
    body = world.object_body[host]
    for rec in world.assets[host].receptacles:
        link_body = body if rec.link == "base" else world.model.body(f"obj_{host}_{rec.link}").id
        rot = world.data.xmat[link_body].reshape(3, 3)
        local = rot.T @ (pos - world.data.xpos[link_body])
        if (abs(local[0] - rec.center[0]) <= rec.half_size[0] + 0.02 and
                abs(local[1] - rec.center[1]) <= rec.half_size[1] + 0.02 and abs(local[2] - rec.height) < 0.06):
            return True
    return False


# ---------------------------------------------------------------------------------------


@dataclass
class ComeHereInstance(TaskInstance):
    instruction: str

    def evaluate(self, ctx: TaskContext) -> Evaluation:
        gap = ctx.agent.horizontal_distance(ctx.user.xy)
        done = gap < COME_HERE_DISTANCE
        return Evaluation(done, done, {"distance_to_user": gap})

    def distance_left(self, ctx):
        return _to_user(ctx)


class ComeHere(Task):
    name = "ComeHere"
    templates = ("Come here.", "Come to me.", "Can you come over here?", "Please come here.",
                 "Come over here, please.", "Could you come to me?")

    def house_conditions(self, house_seed):
        return {"min_user_distance": 3.0}  # LEGENT's evaluation starts at least 3 m apart

    def sample(self, ctx, rng):
        if not _fits(user_leg(ctx)):  # a house too big to cross in an episode
            return None
        return ComeHereInstance(self.word(rng))


@dataclass
class GoToInstance(TaskInstance):
    instruction: str
    target: int

    def evaluate(self, ctx):
        near = ctx.reach_distance(ctx.agent.position, self.target) <= ctx.agent.reach
        done = near and ctx.is_visible(ctx.agent, self.target)
        return Evaluation(done, done)

    def distance_left(self, ctx):
        return _object_distance(ctx, self.target)


class GoTo(Task):
    name = "GoTo"
    templates = ("Go to the {a}.", "Walk over to the {a}.", "Head to the {a}.", "Please go to the {a}.",
                 "Can you go to the {a}?")

    def sample(self, ctx, rng):
        # Not reached at the start: measured to the footprint, as success is (a large bed's
        # centre may be 2 m away and its side within reach).
        options = [o for o in ctx.unique_objects()
                   if ctx.reach_distance(ctx.agent.position, o) > ctx.agent.reach + 0.5]
        # Only a target that can be within reach with its centre in sight (success) from
        # somewhere, in an episode's actions.
        target = _draw(options, rng, lambda o: _fits(stand_leg(ctx, o, "sight")))
        if target is None:
            return None
        return GoToInstance(self.word(rng, a=ctx.name_of(target)), target)


def _pickable(ctx: TaskContext) -> list[int]:
    # Whether each can be reached is checked for the drawn one only (``stand_leg``).
    return ctx.unique_objects(interactable=True)


@dataclass
class PickUpInstance(TaskInstance):
    instruction: str
    target: int

    def evaluate(self, ctx):
        done = ctx.agent.state.held == self.target
        return Evaluation(done, done)

    def distance_left(self, ctx):
        return _object_distance(ctx, self.target)


class PickUp(Task):
    name = "PickUp"
    templates = ("Pick up the {a}.", "Grab the {a}.", "Please pick up the {a}.", "Can you pick up the {a}?",
                 "Take the {a}.")

    def sample(self, ctx, rng):
        target = _draw(_pickable(ctx), rng, lambda o: _fits(stand_leg(ctx, o, "aim"), interactions=1))
        if target is None:
            return None
        return PickUpInstance(self.word(rng, a=ctx.name_of(target)), target)


@dataclass
class BringMeInstance(TaskInstance):
    instruction: str
    target: int

    def evaluate(self, ctx):
        holding = ctx.agent.state.held == self.target
        near = ctx.agent.horizontal_distance(ctx.user.xy) < COME_HERE_DISTANCE
        done = holding and near
        return Evaluation(done, done)

    def distance_left(self, ctx):
        if ctx.agent.state.held == self.target:
            return _to_user(ctx)
        return _object_distance(ctx, self.target) + ctx.geodesic_to(ctx.user.xy)


class BringMe(Task):
    name = "BringMe"
    templates = ("Bring me the {a}.", "Can you bring me the {a}?", "Please bring the {a} to me.",
                 "Fetch me the {a}.", "I need the {a}, bring it here.")

    def sample(self, ctx, rng):
        options = [o for o in _pickable(ctx)
                   if ctx.user.horizontal_distance(ctx.object_centre(o)) > COME_HERE_DISTANCE]

        def achievable(o):  # grab it, then walk up to the user, in an episode's actions
            fetch = stand_leg(ctx, o, "aim")
            return fetch is not None and _fits(fetch, user_leg(ctx, fetch.end, fetch.yaw), interactions=1)

        target = _draw(options, rng, achievable)
        if target is None:
            return None
        return BringMeInstance(self.word(rng, a=ctx.name_of(target)), target)


@dataclass
class WhereIsInstance(TaskInstance):
    instruction: str
    target: int
    receptacle: int
    answers: tuple[str, ...]

    def evaluate(self, ctx):
        done = _said(ctx, list(self.answers))
        # Any speech ends the episode, right or wrong (LEGENT).
        return Evaluation(done, bool(ctx.speech))

    def distance_left(self, ctx):
        return _object_distance(ctx, self.target)


#: LEGENT's Where Is data (the objects and receptacles of LEGENT's released Where Is task data): these objects ...
PAPER_WHERE_IS_OBJECTS = ("orange", "apple", "banana", "cola_can")
#: ... on these receptacles ("table" is any of ours named a table, "countertop" the kitchen counter).
PAPER_WHERE_IS_RECEPTACLES = ("sofa", "chair", "dining_table", "coffee_table", "side_table", "kitchen_counter",
                              "dresser")
#: ``task_options`` for WhereIs that ask LEGENT's questions: ``gym.make(..., task_options=PAPER_WHERE_IS)``.
PAPER_WHERE_IS = {"objects": PAPER_WHERE_IS_OBJECTS, "receptacles": PAPER_WHERE_IS_RECEPTACLES}


def _categories(kind: str, given: Sequence[str] | None) -> tuple[str, ...] | None:
    if given is None:
        return None
    if isinstance(given, str) or not given:
        raise ValueError(f"WhereIs {kind} must be a non-empty list of asset categories, got {given!r}")
    unknown = [c for c in given if not registry.by_category(c)]
    if unknown:
        raise ValueError(f"WhereIs {kind}: no asset has the category {', '.join(map(repr, unknown))}")
    return tuple(given)


class WhereIs(Task):
    """Where is the A? Arguments (``task_options``): ``objects``, the categories that may be
    asked about, and ``receptacles``, those they may rest on (default: any). When either is
    given, every house is generated with one such object on one such receptacle (both drawn
    from the house seed), as LEGENT's data did; :data:`PAPER_WHERE_IS` is LEGENT's set."""

    name = "WhereIs"
    templates = ("Where is the {a}?", "Where's the {a}?", "Do you know where the {a} is?",
                 "Can you tell me where the {a} is?", "I can't find the {a}. Where is it?")

    def __init__(self, objects: Sequence[str] | None = None, receptacles: Sequence[str] | None = None):
        self.objects = _categories("objects", objects)
        self.receptacles = _categories("receptacles", receptacles)

    def house_conditions(self, house_seed):
        if self.objects is None and self.receptacles is None:
            return {}
        rng = np.random.default_rng([house_seed, 0x3E1])  # not the env's stream: other tasks' episodes stay
        objects = self.objects or sorted({c for cs in PLAUSIBLE.values() for c in cs})
        receptacles = self.receptacles or sorted(PLAUSIBLE)
        # A receptacle the layout's rooms cannot hold fails generation; the env draws again.
        return {"require_on": [(str(rng.choice(objects)), str(rng.choice(receptacles)))]}

    def _allowed(self, ctx, target, host) -> bool:
        return ((self.objects is None or ctx.world.assets[target].category in self.objects) and
                (self.receptacles is None or ctx.world.assets[host].category in self.receptacles))

    def sample(self, ctx, rng):
        options = []
        for o in ctx.unique_objects(interactable=True):
            host = ctx.scene.object(o).on
            if host is None or not self._allowed(ctx, o, host):
                continue
            # The answer must name the host unambiguously: no other object shares a name with it.
            host_names = ctx.names_of(host)
            clash = any(n in ctx.names_of(other.id) for other in ctx.scene.objects if other.id != host
                        for n in host_names[:1])
            if not clash:
                options.append((o, host))
        # Only an object that can be found (in sight within 3 m of somewhere), in an episode's actions.
        drawn = _draw(options, rng, lambda pair: _fits(stand_leg(ctx, pair[0], "see"), interactions=1))
        if drawn is None:
            return None
        target, host = drawn
        return WhereIsInstance(self.word(rng, a=ctx.name_of(target)), target, host, tuple(ctx.names_of(host)))


@dataclass
class PutOnInstance(TaskInstance):
    instruction: str
    target: int
    receptacle: int

    def evaluate(self, ctx):
        done = _rests_on(ctx, self.target, self.receptacle)
        return Evaluation(done, done)

    def distance_left(self, ctx):
        if ctx.agent.state.held == self.target:
            return _object_distance(ctx, self.receptacle)
        return _object_distance(ctx, self.target) + 1.0  # + 1: the put still to come


class PutOn(Task):
    name = "PutOn"
    templates = ("Put the {a} on the {b}.", "Place the {a} on the {b}.", "Can you put the {a} on the {b}?",
                 "Move the {a} onto the {b}.", "Please set the {a} on the {b}.")

    def sample(self, ctx, rng):
        items = _pickable(ctx)
        hosts = [o for o in ctx.unique_objects(interactable=False)
                 if any(r.link == "base" and r.clearance > 0.25 and r.area > 0.08
                        for r in ctx.world.assets[o].receptacles)]
        pairs = [(a, b) for a in items for b in hosts if ctx.scene.object(a).on != b]
        fetches: dict[int, Leg | None] = {}

        def achievable(pair):  # grab a, then put it on b where it fits, in an episode's actions
            a, b = pair
            if a not in fetches:
                fetches[a] = stand_leg(ctx, a, "aim")
            fetch = fetches[a]
            return fetch is not None and _fits(fetch, stand_leg(ctx, b, "put", fetch.end, fetch.yaw, item=a),
                                               interactions=2)

        drawn = _draw(pairs, rng, achievable)
        if drawn is None:
            return None
        a, b = drawn
        return PutOnInstance(self.word(rng, a=ctx.name_of(a), b=ctx.name_of(b)), a, b)


TASKS: dict[str, type[Task]] = {t.name: t for t in (ComeHere, GoTo, PickUp, BringMe, WhereIs, PutOn)}


def paper_instruction(task: Task, goal: TaskInstance, ctx: TaskContext) -> str:
    """``goal`` in the words of the paper's template for it (the first of its task's
    ``templates``: "Come here.", "Where is the apple?"), whatever paraphrase the user said.
    Its first word names the task as LEGENT's evaluation reads it (``come``, ``where``)."""
    template = TASKS[task.goal_task(goal)].templates[0]
    target, receptacle = getattr(goal, "target", None), getattr(goal, "receptacle", None)
    names = {"a": ctx.name_of(target) if target is not None else "",
             "b": ctx.name_of(receptacle) if receptacle is not None else ""}
    return template.format(**names)


def make_task(name: str, **options: Any) -> Task:
    """The task ``name`` (one of :data:`TASKS`, or ``Custom``: tasks read from a file, see
    :mod:`legent_gym.tasks.custom`) with its ``options`` (keyword arguments of its class)."""
    from legent_gym.tasks.custom import Custom  # it plays this module's goals

    table: dict[str, type[Task]] = {**TASKS, Custom.name: Custom}
    if name not in table:
        raise ValueError(f"unknown task {name!r}; known: {', '.join(table)}")
    try:
        return table[name](**options)
    except TypeError as err:
        raise ValueError(f"task {name} does not take the options {sorted(options)}: {err}") from None


__all__ = ["TASKS", "make_task", "paper_instruction", "PAPER_WHERE_IS", "ComeHere", "GoTo", "PickUp", "BringMe", "WhereIs", "PutOn"]
