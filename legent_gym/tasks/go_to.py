"""GoTo(A): "Go to the A." Success: A is within reach of the agent (horizontally, to the
nearest point of A's footprint) and visible in its view."""

from __future__ import annotations

from dataclasses import dataclass

from legent_gym.tasks.base import Evaluation, Task, TaskInstance
from legent_gym.tasks.common import draw, fits
from legent_gym.tasks.feasibility import stand_leg
from legent_gym.tasks.registry import register_task


@dataclass
class GoToInstance(TaskInstance):
    instruction: str
    target: int

    def evaluate(self, ctx):
        near = ctx.reach_distance(ctx.agent.position, self.target) <= ctx.agent.reach
        done = near and ctx.is_visible(ctx.agent, self.target)
        return Evaluation(done, done)

    def distance_left(self, ctx):
        return ctx.distance_to_object(self.target)


@register_task
class GoTo(Task):
    name = "GoTo"
    goal_type = GoToInstance
    templates = ("Go to the {a}.", "Walk over to the {a}.", "Head to the {a}.", "Please go to the {a}.",
                 "Can you go to the {a}?")
    code = "goto({a})"
    roles = ("target",)
    kinds = {"goto": "go to the target"}

    def sample(self, ctx, rng):
        # Not reached at the start: measured to the footprint, as success is (a large bed's
        # centre may be 2 m away and its side within reach).
        options = [o for o in ctx.unique_objects()
                   if ctx.reach_distance(ctx.agent.position, o) > ctx.agent.reach + 0.5]
        # Only a target that can be within reach with its centre in sight (success) from
        # somewhere, in an episode's actions.
        target = draw(options, rng, lambda o: fits(stand_leg(ctx, o, "sight")))
        if target is None:
            return None
        return GoToInstance(self.word(rng, a=ctx.name_of(target)), target)
