"""Tasks: what the agent is asked to do in a house and how success is judged.

Each task is one file whose :class:`Task` class carries everything about it (instructions,
goal sampling, success, the expert's intermediate code, its kinds of a tasks file) and
registers itself (:func:`register_task`); the built-in ones (ComeHere, GoTo, PickUp,
BringMe, WhereIs, PutOn; the table is :data:`TASKS`) are imported below, one line each.
A task samples a :class:`TaskInstance` (a goal with its instruction) in a house through a
:class:`TaskContext` (scene, built world, bodies, navigation grid), and judges it with an
:class:`Evaluation` after every action. :mod:`legent_gym.tasks.feasibility` says which
goals an agent can achieve; the task samplers and the experts share it. Tasks know the
world; they know nothing of Gymnasium. docs/adding-a-task.md walks through a new task.
"""

from legent_gym.tasks.base import MAX_ACTIONS, Evaluation, Task, TaskContext, TaskInstance
from legent_gym.tasks.registry import (
    SCENE_TASKS,
    TASKS,
    make_task,
    paper_instruction,
    register_task,
    task_class,
    task_kinds,
    task_of_kind,
    unregister_task,
)

# The built-in tasks, in the paper's order (Table 2): each import registers its task, and
# the import order is the registration order (of TASKS and the env ids).
# isort: off
from legent_gym.tasks.come_here import ComeHere
from legent_gym.tasks.go_to import GoTo
from legent_gym.tasks.pick_up import PickUp
from legent_gym.tasks.bring_me import BringMe
from legent_gym.tasks.where_is import PAPER_WHERE_IS, WhereIs
from legent_gym.tasks.put_on import PutOn
from legent_gym.tasks.custom import Custom
# isort: on

__all__ = ["MAX_ACTIONS", "PAPER_WHERE_IS", "SCENE_TASKS", "TASKS", "BringMe", "ComeHere", "Custom", "Evaluation",
           "GoTo", "PickUp", "PutOn", "Task", "TaskContext", "TaskInstance", "WhereIs", "make_task",
           "paper_instruction", "register_task", "task_class", "task_kinds", "task_of_kind", "unregister_task"]
