"""Task templates -> intermediate code (Table 2 of the paper), with no LLM.

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
expert that takes over mid-episode: once A is held, BringMe's code is just ``goto_user()``.
If the agent holds something it should not (after another policy's actions), the code first
puts it back down where it can.
"""

from __future__ import annotations

from legent_gym.experts.oracle import Oracle
from legent_gym.experts.program import Instruction, Program
from legent_gym.tasks.base import TaskInstance

__all__ = ["task_program", "TEMPLATES"]

TEMPLATES = {
    "ComeHere": "goto_user()",
    "GoTo": "goto(a)",
    "PickUp": "goto(a) target(a) interact()",
    "BringMe": "goto(a) target(a) interact() goto_user()",
    "WhereIs": 'find(a) speak("It\'s on the C.")',
    "PutOn": "goto(a) target(a) interact() goto(b) target(b) interact()",
}


def _object(goal: TaskInstance, role: str) -> int:
    """The goal's object id in ``role`` (``"target"``, ``"receptacle"``): every goal whose
    template names that object has it."""
    object_id = getattr(goal, role, None)
    if object_id is None:
        raise ValueError(f"a {type(goal).__name__} goal has no {role}")
    return object_id


def _fetch(a: int) -> list[Instruction]:
    return [Instruction("goto", a), Instruction("target", a), Instruction("interact")]


def task_program(oracle: Oracle) -> Program:
    """The intermediate code that completes the oracle's current task from the current state."""
    goal, name, held = oracle.goal, oracle.task_name, oracle.held
    a = getattr(goal, "target", None)
    out: list[Instruction] = []
    if held is not None and held != a and name in ("PickUp", "BringMe", "PutOn"):
        # Hands full with the wrong thing: put it back where it came from first.
        home = oracle.home_of(held)
        if home is not None:
            out += [Instruction("goto", home), Instruction("target", home), Instruction("put")]
    match name:
        case "ComeHere":
            out.append(Instruction("goto_user"))
        case "GoTo":
            out.append(Instruction("goto", a))
        case "PickUp":
            if held != a:
                out += _fetch(_object(goal, "target"))
        case "BringMe":
            if held != a:
                out += _fetch(_object(goal, "target"))
            out.append(Instruction("goto_user"))
        case "WhereIs":
            out += [Instruction("find", a),
                    Instruction("speak", f"It's on the {oracle.name_of(_object(goal, 'receptacle'))}.")]
        case "PutOn":
            b = _object(goal, "receptacle")
            if held != a:
                out += _fetch(_object(goal, "target"))
            out += [Instruction("goto", b), Instruction("target", b), Instruction("interact")]
        case _:
            raise ValueError(f"no template for task {name!r}; known: {', '.join(TEMPLATES)}")
    return tuple(out)
