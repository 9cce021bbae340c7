"""What the household tasks' files share: drawing a goal the expert can complete within the
episode's actions, and the distance to the user.

Goals are drawn only among those the task expert can complete within the paper's
25-action cap (:mod:`legent_gym.tasks.feasibility`: somewhere to stand to see or act on
the objects, and an estimated plan of at most ``PLAN_BUDGET`` actions).
"""

from __future__ import annotations

from legent_gym.tasks.base import TaskContext
from legent_gym.tasks.feasibility import PLAN_BUDGET, Leg

#: ComeHere's and BringMe's success: the agent within this many metres (horizontal) of the user.
COME_HERE_DISTANCE = 2.0


def to_user(ctx: TaskContext) -> float:
    """Geodesic metres left until the agent is within ComeHere's distance of the user."""
    return max(ctx.geodesic_to(ctx.user.xy) - COME_HERE_DISTANCE, 0.0)


def draw(options: list, rng, achievable):
    """A uniformly drawn option that passes ``achievable`` (checked lazily, in the drawn
    order, so only the drawn goal pays for the check), or None."""
    for i in rng.permutation(len(options)):
        if achievable(options[int(i)]):
            return options[int(i)]
    return None


def fits(*legs: Leg | None, interactions: int = 0) -> bool:
    """Every walk exists, and with the interactions the expert's plan stays within budget."""
    total = interactions
    for leg in legs:
        if leg is None:
            return False
        total += leg.actions
    return total <= PLAN_BUDGET


def pickable(ctx: TaskContext) -> list[int]:
    """The objects a goal may ask to pick up: interactable, their category once in the house."""
    # Whether each can be reached is checked for the drawn one only (``stand_leg``).
    return ctx.unique_objects(interactable=True)
