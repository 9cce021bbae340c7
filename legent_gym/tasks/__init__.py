"""Tasks: what the agent is asked to do in a house and how success is judged.

A :class:`Task` family (ComeHere, GoTo, PickUp, BringMe, WhereIs, PutOn; the table is
:data:`TASKS`) samples a :class:`TaskInstance` (a goal with its instruction) in a house
through a :class:`TaskContext` (scene, built world, bodies, navigation grid), and judges it
with an :class:`Evaluation` after every action. :mod:`legent_gym.tasks.feasibility` says
which goals an agent can achieve; the task samplers and the experts share it. Tasks know
the world; they know nothing of Gymnasium.
"""

from legent_gym.tasks.base import MAX_ACTIONS, Evaluation, Task, TaskContext, TaskInstance
from legent_gym.tasks.household import (
    PAPER_WHERE_IS,
    TASKS,
    BringMe,
    ComeHere,
    GoTo,
    PickUp,
    PutOn,
    WhereIs,
    make_task,
)

__all__ = ["MAX_ACTIONS", "PAPER_WHERE_IS", "TASKS", "BringMe", "ComeHere", "Evaluation", "GoTo", "PickUp", "PutOn",
           "Task", "TaskContext", "TaskInstance", "WhereIs", "make_task"]
