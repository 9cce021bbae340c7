"""Tasks written for one scene (by an LLM or a person), read from a tasks file.

A tasks file (``legent-gym tasks generate``; JSON lines) has a header line and one line per
task; the lines whose ``status`` is ``"kept"`` are tasks (:class:`TaskSpec`):

* ``kind``: what success means, judged by the registered task whose ``kinds`` hold it
  (:func:`~legent_gym.tasks.registry.task_of_kind`): ``come`` (ComeHere: within 2 m of the
  user), ``goto`` (GoTo: ``target`` within reach and visible), ``take`` (PickUp:
  ``target`` held), ``bring`` (BringMe: ``target`` held within 2 m of the user), ``put``
  (PutOn: ``target`` resting on ``receptacle``), ``where`` and ``exist`` (WhereIs: the
  agent's speech names ``receptacle``, what ``target`` stands on);
* ``instruction``: what the user says; ``code``: the intermediate code that does it
  (:mod:`legent_gym.experts.program`);
* ``target``, ``receptacle``: the object ids the kind's task needs (its ``roles``).

:class:`Custom` plays a file's tasks in one scene: each goal is the template task's own
goal (its ``goal_for``, so the experts, which write the template's code for it, can
complete it), with the file's instruction. ``order="random"`` (default) draws a task from
the episode's generator (a seeded reset gives the same task); ``"sequential"`` plays them
in the file's order, round and round.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from legent_gym.tasks.base import Task, TaskContext, TaskInstance
from legent_gym.tasks.registry import register_task, task_of_kind

#: The first line of a tasks file names this format.
TASKS_FORMAT = "legent-gym-tasks"
TASKS_VERSION = 1


class TaskSpec(BaseModel):
    """One task for a scene (see the module docstring)."""

    model_config = ConfigDict(extra="ignore")

    kind: str
    instruction: str = Field(min_length=1, max_length=500)
    code: str = Field(min_length=1, max_length=2000)
    target: int | None = None
    receptacle: int | None = None

    @field_validator("kind")
    @classmethod
    def _known_kind(cls, kind: str) -> str:
        task_of_kind(kind)  # ValueError naming the known kinds
        return kind

    @model_validator(mode="after")
    def _objects(self) -> TaskSpec:
        for role in self.task.roles:
            if getattr(self, role) is None:
                raise ValueError(f"a {self.kind!r} task needs a {role} object id")
        return self

    @property
    def task(self) -> type[Task]:
        """The registered task that judges this kind."""
        return task_of_kind(self.kind)

    @property
    def template(self) -> str:
        """The name of :attr:`task`."""
        return self.task.name

    def object_ids(self) -> list[int]:
        return [getattr(self, role) for role in self.task.roles]


def goal_of(spec: TaskSpec, ctx: TaskContext) -> TaskInstance:
    """The template task's goal for ``spec`` in ``ctx``'s scene; ``ValueError`` if the scene
    lacks one of its objects."""
    ids = {o.id for o in ctx.scene.objects}
    missing = [i for i in spec.object_ids() if i not in ids]
    if missing:
        raise ValueError(f"task {spec.instruction!r}: no object with id {missing[0]} in scene {ctx.scene.name!r}")
    return spec.task.goal_for(ctx, spec.instruction, spec.target, spec.receptacle)


def read_tasks(path: str | Path) -> list[TaskSpec]:
    """The kept tasks of a tasks file; ``ValueError`` naming the file and line if it is not one."""
    return read_tasks_file(path)[1]


def read_tasks_file(path: str | Path) -> tuple[dict[str, Any], list[TaskSpec]]:
    """A tasks file's header (``{}`` if it has none) and kept tasks; ``ValueError`` naming
    the file and line if it is not one."""
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except OSError as err:
        raise ValueError(f"{path}: {err.strerror or err}") from None
    out: list[TaskSpec] = []
    header: dict[str, Any] = {}
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            record = json.loads(line)
        except json.JSONDecodeError as err:
            raise ValueError(f"{path}:{number}: not JSON: {err}") from None
        if not isinstance(record, dict):
            raise ValueError(f"{path}:{number}: not a JSON object")
        if number == 1 and record.get("format") == TASKS_FORMAT:
            header = record
            continue
        if record.get("status", "kept") != "kept":
            continue
        try:
            out.append(TaskSpec.model_validate(record))
        except ValidationError as err:
            raise ValueError(f"{path}:{number}: not a task: {err.errors()[0]['msg']}") from None
    if not out:
        raise ValueError(f"{path}: no kept task")
    return header, out


@register_task(layouts=False)
class Custom(Task):
    """The tasks of a tasks file (``tasks``: its path, or a list of :class:`TaskSpec` or
    dicts), in ``order`` ``"random"`` or ``"sequential"`` (see the module docstring)."""

    name = "Custom"

    def __init__(self, tasks: str | Path | Sequence[TaskSpec | dict[str, Any]] | None = None,
                 order: str = "random"):
        if tasks is None:
            raise ValueError("the Custom task needs tasks: a tasks file (legent-gym tasks generate) or a list")
        if order not in ("random", "sequential"):
            raise ValueError(f"order must be 'random' or 'sequential', got {order!r}")
        #: The scene's objects the tasks were written for ({id: asset}; None: not recorded).
        self.objects: dict[int, str] | None = None
        if isinstance(tasks, str | Path):
            header, self.tasks = read_tasks_file(tasks)
            if isinstance(header.get("objects"), list):
                self.objects = {int(i): str(a) for i, a in header["objects"]}
        else:
            self.tasks = [t if isinstance(t, TaskSpec) else TaskSpec.model_validate(t) for t in tasks]
            if not self.tasks:
                raise ValueError("the Custom task needs at least one task")
        self.order = order
        #: The index of the task the next sequential episode plays.
        self.next_index = 0
        #: The spec of the current goal.
        self.current: TaskSpec | None = None

    def sample(self, ctx: TaskContext, rng: np.random.Generator) -> TaskInstance:
        if self.objects is not None:
            have = {o.id: o.asset for o in ctx.scene.objects}
            wrong = [i for i, asset in self.objects.items() if have.get(i) != asset]
            if wrong:
                raise ValueError(f"the tasks were written for another scene than {ctx.scene.name!r}: object "
                                 f"{wrong[0]} is {have.get(wrong[0])!r} there, {self.objects[wrong[0]]!r} in "
                                 "the tasks file")
        if self.order == "random":
            index = int(rng.integers(len(self.tasks)))
        else:
            index, self.next_index = self.next_index % len(self.tasks), self.next_index + 1
        self.current = self.tasks[index]
        return goal_of(self.current, ctx)

    def goal_task(self, goal: TaskInstance) -> str:
        return self.current.template if self.current is not None else self.name
