"""Experts: intermediate code executed by the motion planners, one optimal action at a time.

* :class:`ProgramExecutor` runs code written by anyone (a template, an LLM, a person): it
  keeps a program counter and asks the planner of the current instruction for the next
  action; instructions that act once (``interact()``, ``speak(...)``) advance it at once.
* :class:`Expert` is the task expert: at every call it writes the task's code for the
  current state (:func:`~legent_gym.experts.templates.task_program`) and executes its first
  action. It keeps no plan between calls beyond cached standing points, so it can take over
  after any other policy's actions (DAgger), like the BabyAI bot.

Both return a *step* (a tuple of action primitives) or the action in the env's own action
space (:meth:`Expert.action`: action code for ``action_type="text"``, a dict for
``"continuous"``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

from legent_gym.agent.actions import (
    Action,
    Close,
    Finish,
    Grab,
    Interact,
    Open,
    Put,
    Speak,
    format_actions,
)
from legent_gym.envs.action_spaces import actions_to_dict
from legent_gym.experts.oracle import Oracle
from legent_gym.experts.planners import Planner, PlanningError
from legent_gym.experts.program import ONE_SHOT, Instruction, Program, check_program, parse_program
from legent_gym.experts.templates import task_program

__all__ = ["Expert", "ProgramExecutor", "PlanningError"]

# Each constructor checks its target itself (Grab and Put refuse a door id: TypeError).
_ONE_SHOT_ACTION = cast(dict[str, Callable[[int | str | None], Action]],
                        {"interact": Interact, "grab": Grab, "put": Put, "open": Open, "close": Close})


def one_shot(instruction: Instruction) -> Action:
    """The primitive of an instruction that acts once."""
    if instruction.name == "speak":
        return Speak(instruction.text_arg())
    if instruction.name == "finish":
        return Finish()
    return _ONE_SHOT_ACTION[instruction.name](instruction.arg)


def _interaction_follows(program: Program, index: int) -> bool:
    return index < len(program) and program[index].name in _ONE_SHOT_ACTION


def _targets(program: Program, index: int, object_id) -> bool:
    """Whether instruction ``index`` aims at ``object_id`` (so the walk before it stands
    where it can be aimed at, and leaves the facing to it)."""
    return index < len(program) and program[index].name == "target" and program[index].arg == object_id


def next_step(planner: Planner, program: Program, pc: int) -> tuple[tuple, int]:
    """The next action of ``program`` from instruction ``pc`` on, and the new counter.

    Planned instructions that are already done are skipped; a ``target`` whose aim is
    complete after this action takes the interaction that follows it into the same action.
    An exhausted program yields ``finish()``.
    """
    while pc < len(program):
        ins = program[pc]
        if ins.name in ONE_SHOT:
            return (one_shot(ins),), pc + 1
        if ins.name == "target":
            step, aimed = planner.target(ins.object_arg())
            if step is None:
                pc += 1
                continue
            if aimed and _interaction_follows(program, pc + 1):
                return step + (one_shot(program[pc + 1]),), pc + 2
            return step, pc
        if ins.name == "goto_user":
            step = planner.goto_user()
        elif ins.name == "goto":
            step = planner.goto(ins.object_arg(), then_target=_targets(program, pc + 1, ins.arg))
        else:
            step = getattr(planner, ins.name)(ins.arg)
        if step is None:
            pc += 1
            continue
        return step, pc
    return (Finish(),), pc


class _ActionSpaceMixin:
    oracle: Oracle

    def step(self) -> tuple:
        """The next action as a step of primitives (each subclass says how)."""
        raise NotImplementedError

    def action(self):
        """The next action in the env's own action space."""
        step = self.step()
        if self.oracle.action_type == "text":
            return format_actions(step)
        return actions_to_dict(step, limits=self.oracle.limits)


class ProgramExecutor(_ActionSpaceMixin):
    """Runs one program (intermediate code) in an env's current episode.

    Args:
        env: the env (or a wrapper of it), already reset.
        program: the code as text or a parsed :data:`Program`; object and door ids are
            checked against the episode's scene (``ProgramError`` if one is unknown).
    """

    def __init__(self, env, program: str | Program):
        self.oracle = Oracle(env)
        self.planner = Planner(self.oracle)
        self.program = parse_program(program) if isinstance(program, str) else tuple(program)
        check_program(self.program, self.oracle.object_ids(), self.oracle.door_ids())
        self.pc = 0

    @property
    def done(self) -> bool:
        return self.pc >= len(self.program)

    def step(self) -> tuple:
        """The next action (a step of primitives); ``finish()`` once the program is done.
        Raises :class:`PlanningError` when the current instruction cannot be carried out."""
        step, self.pc = next_step(self.planner, self.program, self.pc)
        return step


class Expert(_ActionSpaceMixin):
    """The task expert of an env: optimal actions from any state of any episode.

    Args:
        env: a Legent env (or a wrapper of one). The expert follows the env across resets.
        find_strategy: how ``find(a)`` proceeds while ``a`` is out of view: ``"direct"``
            (LEGENT's: turn and walk straight to it, knowing where it is) or ``"scan"``
            (look around in place first, turning right until it is in view), whose
            demonstrations never turn towards what the image does not show.
    """

    def __init__(self, env, find_strategy: str = "direct"):
        self.oracle = Oracle(env)
        self.planner = Planner(self.oracle, find_strategy)
        #: Why the last call could not plan (None when it could): then the action is finish().
        self.problem: str | None = None

    def program(self) -> Program:
        """The intermediate code that completes the task from the current state."""
        return task_program(self.oracle)

    def step(self) -> tuple:
        """The next optimal action (a step of primitives).

        When no plan exists (the goal became unreachable), returns ``finish()`` and says
        why in :attr:`problem`."""
        try:
            step, _ = next_step(self.planner, self.program(), 0)
            self.problem = None
            return step
        except PlanningError as err:
            self.problem = str(err)
            return (Finish(),)
