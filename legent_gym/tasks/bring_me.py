"""BringMe(A): "Bring me the A." Success: the agent holds A within 2.0 m of the user."""

from __future__ import annotations

from dataclasses import dataclass

from legent_gym.tasks.base import Evaluation, Task, TaskInstance
from legent_gym.tasks.common import COME_HERE_DISTANCE, draw, fits, pickable, to_user
from legent_gym.tasks.feasibility import stand_leg, user_leg
from legent_gym.tasks.registry import register_task


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
            return to_user(ctx)
        return ctx.distance_to_object(self.target) + ctx.geodesic_to(ctx.user.xy)


@register_task
class BringMe(Task):
    name = "BringMe"
    goal_type = BringMeInstance
    templates = ("Bring me the {a}.", "Can you bring me the {a}?", "Please bring the {a} to me.",
                 "Fetch me the {a}.", "I need the {a}, bring it here.")
    code = "goto({a}) target({a}) interact() goto_user()"
    roles = ("target",)
    kinds = {"bring": "bring the target to the user"}

    def sample(self, ctx, rng):
        options = [o for o in pickable(ctx)
                   if ctx.user.horizontal_distance(ctx.object_centre(o)) > COME_HERE_DISTANCE]

        def achievable(o):  # grab it, then walk up to the user, in an episode's actions
            fetch = stand_leg(ctx, o, "aim")
            return fetch is not None and fits(fetch, user_leg(ctx, fetch.end, fetch.yaw), interactions=1)

        target = draw(options, rng, achievable)
        if target is None:
            return None
        return BringMeInstance(self.word(rng, a=ctx.name_of(target)), target)
