"""PutOn(A, B): "Put the A on the B." Success: A rests on B (not held, on one of B's
surfaces, at rest)."""

from __future__ import annotations

from dataclasses import dataclass

from legent_gym.tasks.base import Evaluation, Task, TaskContext, TaskInstance
from legent_gym.tasks.common import draw, fits, pickable
from legent_gym.tasks.feasibility import Leg, stand_leg
from legent_gym.tasks.registry import register_task


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
            return ctx.distance_to_object(self.receptacle)
        return ctx.distance_to_object(self.target) + 1.0  # + 1: the put still to come


@register_task
class PutOn(Task):
    name = "PutOn"
    goal_type = PutOnInstance
    templates = ("Put the {a} on the {b}.", "Place the {a} on the {b}.", "Can you put the {a} on the {b}?",
                 "Move the {a} onto the {b}.", "Please set the {a} on the {b}.")
    code = "goto({a}) target({a}) interact() goto({b}) target({b}) interact()"
    roles = ("target", "receptacle")
    kinds = {"put": "put the target on the receptacle"}

    def sample(self, ctx, rng):
        items = pickable(ctx)
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
            return fetch is not None and fits(fetch, stand_leg(ctx, b, "put", fetch.end, fetch.yaw, item=a),
                                              interactions=2)

        drawn = draw(pairs, rng, achievable)
        if drawn is None:
            return None
        a, b = drawn
        return PutOnInstance(self.word(rng, a=ctx.name_of(a), b=ctx.name_of(b)), a, b)


    @classmethod
    def spec_problem(cls, ctx, target, receptacle):
        if ctx.scene.object(target).on == receptacle:
            return f"target {target} ({ctx.name_of(target)}) is on {receptacle} already"
        return None
