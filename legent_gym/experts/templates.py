"""Task -> intermediate code (Table 2 of the paper), with no LLM.

Each task class carries its code (:attr:`~legent_gym.tasks.base.Task.code`), ``{a}`` and
``{b}`` standing for the goal's target and receptacle, ``{b_name}`` for the receptacle's
name:

=============  ======================  ======================================================
task           instruction             intermediate code
=============  ======================  ======================================================
ComeHere       "Come here."            ``goto_user()``
GoTo(A)        "Go to the A."          ``goto(a)``
PickUp(A)      "Pick up the A."        ``goto(a) target(a) interact()``
BringMe(A)     "Bring me the A."       ``goto(a) target(a) interact() goto_user()``
WhereIs(A)     "Where is the A?"       ``find(a) speak("It's on the C.")``
PutOn(A, B)    "Put the A on the B."   ``goto(a) target(a) interact() goto(b) target(b) interact()``
=============  ======================  ======================================================

:func:`task_program` writes the code for the state the episode is in now, so it serves an
expert that takes over mid-episode: code that starts by fetching A
(:data:`~legent_gym.tasks.base.FETCH_CODE`) skips the fetch once A is held (BringMe's code
is then just ``goto_user()``), and first puts back down, where it can, anything else the
agent holds (after another policy's actions).
"""

from __future__ import annotations

import json
from dataclasses import replace

from legent_gym.experts.oracle import Oracle
from legent_gym.experts.program import Instruction, Program, parse_program
from legent_gym.tasks.base import CODE_FIELDS, FETCH_CODE, Task, TaskInstance

__all__ = ["code_template", "task_program"]

#: What each of a task code's fields shows in :func:`code_template` (Table 2's letters).
SHOWN = {"a": "a", "b": "b", "b_name": "C"}


def code_template(task: type[Task]) -> str:
    """The task's code as Table 2 writes it: ``goto(a) target(a) interact() goto_user()``."""
    return task.code.format(**SHOWN)


def _object(goal: TaskInstance, role: str) -> int:
    """The goal's object id in ``role`` (``"target"``, ``"receptacle"``): every goal whose
    code names that object has it."""
    object_id = getattr(goal, role, None)
    if object_id is None:
        raise ValueError(f"a {type(goal).__name__} goal has no {role}")
    return object_id


def _fill(code: str, goal: TaskInstance, oracle: Oracle) -> Program:
    """``code`` with the goal's objects in its fields, parsed (none for no code: all done)."""
    if not code.strip():
        return ()
    used = {field for field in CODE_FIELDS if "{" + field + "}" in code}
    values: dict[str, object] = {}
    if "a" in used:
        values["a"] = _object(goal, "target")
    if used & {"b", "b_name"}:
        b = _object(goal, "receptacle")
        values.update(b=b, b_name=json.dumps(oracle.name_of(b), ensure_ascii=False)[1:-1])  # inside quotes
    return tuple(replace(i, position=-1) for i in parse_program(code.format(**values)))


def task_program(oracle: Oracle) -> Program:
    """The intermediate code that completes the oracle's current task from the current state."""
    task, goal, held = oracle.task, oracle.goal, oracle.held
    if not task.code:
        raise ValueError(f"task {task.name!r} has no intermediate code (its class's ``code``)")
    a = getattr(goal, "target", None)
    out: list[Instruction] = []
    code = task.code
    if task.fetches_target():
        if held is not None and held != a:
            # Hands full with the wrong thing: put it back where it came from first.
            home = oracle.home_of(held)
            if home is not None:
                out += [Instruction("goto", home), Instruction("target", home), Instruction("put")]
        elif held == a:
            code = code.removeprefix(FETCH_CODE)
    return (*out, *_fill(code, goal, oracle))
