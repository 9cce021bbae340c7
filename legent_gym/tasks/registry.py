"""The task registry: every task class, by name and by the kinds of a tasks file it judges.

A task registers itself with the :func:`register_task` decorator on its class (ManiSkill's
style); :mod:`legent_gym.tasks` imports each built-in task's file, one line each, so
``import legent_gym`` registers them all, and the env ids follow from :data:`TASKS`
(:mod:`legent_gym.envs.registration`). Nothing else names a task: the envs, the experts,
the oracle, custom task files, the LLM task generator and the docs read the registered
classes.
"""

from __future__ import annotations

import string
from collections.abc import Callable
from typing import Any, TypeVar, overload

from legent_gym.tasks.base import CODE_FIELDS, Task, TaskContext, TaskInstance

#: The registered tasks with an env id per layout (``Legent/<name>-<Layout>-v0``), in
#: registration order.
TASKS: dict[str, type[Task]] = {}
#: The registered tasks played in a given scene, with no layout ids (``Custom``).
SCENE_TASKS: dict[str, type[Task]] = {}

T = TypeVar("T", bound=Task)


def _check(cls: type[Task]) -> None:
    if not (isinstance(cls, type) and issubclass(cls, Task)):
        raise TypeError(f"register_task takes a Task subclass, got {cls!r}")
    if not cls.name or not cls.name.isidentifier():
        raise ValueError(f"a task's name must be an identifier (it goes into env ids), got {cls.name!r}")
    if cls.name in TASKS or cls.name in SCENE_TASKS:
        raise ValueError(f"a task named {cls.name!r} is registered already")
    fields = {field for _, field, _, _ in string.Formatter().parse(cls.code) if field is not None}
    if not fields <= set(CODE_FIELDS):
        raise ValueError(f"{cls.name}.code names {sorted(fields - set(CODE_FIELDS))}; it may name only "
                         f"{', '.join('{' + f + '}' for f in CODE_FIELDS)}")
    taken = task_kinds()
    for kind in cls.kinds:
        if kind in taken:
            raise ValueError(f"{cls.name} judges the kind {kind!r}, which {taken[kind].name} judges already")


@overload
def register_task(cls: type[T], *, layouts: bool = True) -> type[T]: ...


@overload
def register_task(cls: None = None, *, layouts: bool = True) -> Callable[[type[T]], type[T]]: ...


def register_task(cls: type[T] | None = None, *, layouts: bool = True) -> type[T] | Callable[[type[T]], type[T]]:
    """Register a task class (a decorator: ``@register_task`` or
    ``@register_task(layouts=False)``). With ``layouts``, the task gets an env id per layout
    once :func:`legent_gym.envs.registration.register_envs` runs (``import legent_gym``
    runs it; a task registered later calls it again). ``ValueError`` for a name taken, a
    kind another task judges, or code naming an unknown field."""

    def add(task: type[T]) -> type[T]:
        _check(task)
        (TASKS if layouts else SCENE_TASKS)[task.name] = task
        return task

    return add if cls is None else add(cls)


def unregister_task(name: str) -> None:
    """Remove a registered task (a test's toy task, when the test is over)."""
    if TASKS.pop(name, None) is None and SCENE_TASKS.pop(name, None) is None:
        raise ValueError(f"no task named {name!r} is registered")


def task_kinds() -> dict[str, type[Task]]:
    """Every kind of a tasks file, with the registered task that judges it."""
    return {kind: task for task in (*TASKS.values(), *SCENE_TASKS.values()) for kind in task.kinds}


def task_of_kind(kind: str) -> type[Task]:
    """The registered task that judges ``kind``; ``ValueError`` naming the known kinds."""
    kinds = task_kinds()
    if kind not in kinds:
        raise ValueError(f"unknown kind {kind!r}; known: {', '.join(map(repr, kinds))}")
    return kinds[kind]


def task_class(name: str) -> type[Task]:
    """The registered task ``name``; ``ValueError`` naming the known tasks."""
    table = {**TASKS, **SCENE_TASKS}
    if name not in table:
        raise ValueError(f"unknown task {name!r}; known: {', '.join(table)}")
    return table[name]


def make_task(name: str, **options: Any) -> Task:
    """The task ``name`` (one of :data:`TASKS`, or ``Custom``: tasks read from a file, see
    :mod:`legent_gym.tasks.custom`) with its ``options`` (keyword arguments of its class)."""
    cls = task_class(name)
    try:
        return cls(**options)
    except TypeError as err:
        raise ValueError(f"task {name} does not take the options {sorted(options)}: {err}") from None


def paper_instruction(task: Task, goal: TaskInstance, ctx: TaskContext) -> str:
    """``goal`` in the words of the paper's template for it (the first of its task's
    ``templates``: "Come here.", "Where is the apple?"), whatever paraphrase the user said.
    Its first word names the task as LEGENT's evaluation reads it (``come``, ``where``)."""
    template = task_class(task.goal_task(goal)).templates[0]
    target, receptacle = getattr(goal, "target", None), getattr(goal, "receptacle", None)
    names = {"a": ctx.name_of(target) if target is not None else "",
             "b": ctx.name_of(receptacle) if receptacle is not None else ""}
    return template.format(**names)


__all__ = ["SCENE_TASKS", "TASKS", "make_task", "paper_instruction", "register_task", "task_class", "task_kinds",
           "task_of_kind", "unregister_task"]
