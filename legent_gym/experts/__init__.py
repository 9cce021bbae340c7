"""Experts: the paper's intermediate code, turned into optimal controls by motion planners.

* :mod:`~legent_gym.experts.program`: the intermediate code and its parser;
* :mod:`~legent_gym.experts.oracle`: the one interface through which experts read
  privileged state;
* :mod:`~legent_gym.experts.planners`: a motion planner per instruction;
* :mod:`~legent_gym.experts.templates`: task -> code (Table 2 of the paper, each task's ``code``);
* :mod:`~legent_gym.experts.expert`: :class:`Expert` (the task expert, replanning from any
  state) and :class:`ProgramExecutor` (runs code written by anyone).
"""

from legent_gym.experts.expert import Expert, ProgramExecutor
from legent_gym.experts.oracle import Oracle
from legent_gym.experts.planners import PlanningError
from legent_gym.experts.program import Instruction, ProgramError, format_program, parse_program
from legent_gym.experts.templates import code_template, task_program

__all__ = ["Expert", "Instruction", "Oracle", "PlanningError", "ProgramError", "ProgramExecutor", "code_template",
           "format_program", "parse_program", "task_program"]
