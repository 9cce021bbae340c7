"""PickUp(A): "Pick up the A." Success: the agent holds A."""

from __future__ import annotations

from dataclasses import dataclass

from legent_gym.tasks.base import Evaluation, Task, TaskInstance
from legent_gym.tasks.common import draw, fits, pickable
from legent_gym.tasks.feasibility import stand_leg
from legent_gym.tasks.registry import register_task


@dataclass
class PickUpInstance(TaskInstance):
    instruction: str
    target: int

    def evaluate(self, ctx):
        done = ctx.agent.state.held == self.target
        return Evaluation(done, done)

    def distance_left(self, ctx):
        return ctx.distance_to_object(self.target)


@register_task
class PickUp(Task):
    name = "PickUp"
    goal_type = PickUpInstance
    templates = ("Pick up the {a}.", "Grab the {a}.", "Please pick up the {a}.", "Can you pick up the {a}?",
                 "Take the {a}.")
    code = "goto({a}) target({a}) interact()"
    roles = ("target",)
    kinds = {"take": "pick up the target"}

    def sample(self, ctx, rng):
        target = draw(pickable(ctx), rng, lambda o: fits(stand_leg(ctx, o, "aim"), interactions=1))
        if target is None:
            return None
        return PickUpInstance(self.word(rng, a=ctx.name_of(target)), target)
