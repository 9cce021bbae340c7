"""ComeHere: "Come here." Success: the agent is within 2.0 m (horizontal) of the user,
checked after every action (LEGENT's rule)."""

from __future__ import annotations

from dataclasses import dataclass

from legent_gym.tasks.base import Evaluation, Task, TaskContext, TaskInstance
from legent_gym.tasks.common import COME_HERE_DISTANCE, fits, to_user
from legent_gym.tasks.feasibility import user_leg
from legent_gym.tasks.registry import register_task


@dataclass
class ComeHereInstance(TaskInstance):
    instruction: str

    def evaluate(self, ctx: TaskContext) -> Evaluation:
        gap = ctx.agent.horizontal_distance(ctx.user.xy)
        done = gap < COME_HERE_DISTANCE
        return Evaluation(done, done, {"distance_to_user": gap})

    def distance_left(self, ctx):
        return to_user(ctx)


@register_task
class ComeHere(Task):
    name = "ComeHere"
    goal_type = ComeHereInstance
    templates = ("Come here.", "Come to me.", "Can you come over here?", "Please come here.",
                 "Come over here, please.", "Could you come to me?")
    code = "goto_user()"
    kinds = {"come": "come to the user; no target"}

    def house_conditions(self, house_seed):
        return {"min_user_distance": 3.0}  # LEGENT's evaluation starts at least 3 m apart

    def sample(self, ctx, rng):
        if not fits(user_leg(ctx)):  # a house too big to cross in an episode
            return None
        return ComeHereInstance(self.word(rng))
