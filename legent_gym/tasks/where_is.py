"""WhereIs(A): "Where is the A?" Success: the agent's speech names A's receptacle (its name
or a synonym, a lower-cased substring match as in LEGENT); any speech ends the episode."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from legent_gym.tasks.base import Evaluation, Task, TaskContext, TaskInstance
from legent_gym.tasks.common import draw, fits
from legent_gym.tasks.feasibility import stand_leg
from legent_gym.tasks.registry import register_task
from legent_gym.world.assets import registry
from legent_gym.world.generation.small_objects import PLAUSIBLE


def _said(ctx: TaskContext, names: list[str]) -> bool:
    return any(name in text.lower() for text in ctx.speech for name in names)


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
        return ctx.distance_to_object(self.target)


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


@register_task
class WhereIs(Task):
    """Where is the A? Arguments (``task_options``): ``objects``, the categories that may be
    asked about, and ``receptacles``, those they may rest on (default: any). When either is
    given, every house is generated with one such object on one such receptacle (both drawn
    from the house seed), as LEGENT's data did; :data:`PAPER_WHERE_IS` is LEGENT's set."""

    name = "WhereIs"
    goal_type = WhereIsInstance
    templates = ("Where is the {a}?", "Where's the {a}?", "Do you know where the {a} is?",
                 "Can you tell me where the {a} is?", "I can't find the {a}. Where is it?")
    code = 'find({a}) speak("It\'s on the {b_name}.")'
    roles = ("target", "receptacle")
    kinds = {"where": "say where the target is: the receptacle is what it stands on",
             "exist": "is there such a thing? answer where it is: the receptacle is what it stands on"}

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
        drawn = draw(options, rng, lambda pair: fits(stand_leg(ctx, pair[0], "see"), interactions=1))
        if drawn is None:
            return None
        target, host = drawn
        return WhereIsInstance(self.word(rng, a=ctx.name_of(target)), target, host, tuple(ctx.names_of(host)))

    @classmethod
    def goal_for(cls, ctx, instruction, target=None, receptacle=None):
        return WhereIsInstance(instruction, target, receptacle, tuple(ctx.names_of(receptacle)))

    @classmethod
    def spec_problem(cls, ctx, target, receptacle):
        host = ctx.scene.object(target).on
        if host == receptacle:
            return None
        where = "the floor" if host is None else f"{ctx.name_of(host)} ({host})"
        return (f"target {target} ({ctx.name_of(target)}) stands on {where}, not on {receptacle} "
                f"({ctx.name_of(receptacle)})")
