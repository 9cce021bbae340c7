"""The embodied agent: its body, and the action language it reads and writes.

* :mod:`legent_gym.agent.body`: :class:`Body`, a kinematic, person-sized avatar (the agent
  or the user) that moves without passing through things and interacts through the centre
  of its view; every primitive returns an :class:`Outcome`.
* :mod:`legent_gym.agent.actions`: LEGENT's action code (``move_forward(1.2),
  rotate_right(-30)``): the primitives, :func:`parse_actions`, :func:`format_actions`,
  :class:`ActionLimits` and :func:`clip_action`.
* :mod:`legent_gym.agent.clearance`: how far a body can walk (its disc swept against the
  world's collision geometry).
"""

from legent_gym.agent.actions import (
    ACTION_TYPES,
    Action,
    ActionLimits,
    ActionParseError,
    Close,
    Finish,
    Grab,
    Interact,
    MoveForward,
    Open,
    Put,
    RotateDown,
    RotateRight,
    Speak,
    Step,
    clip_action,
    clip_step,
    format_action,
    format_actions,
    parse_actions,
)
from legent_gym.agent.body import DEFAULT_REACH, PITCH_RANGE, Body, BodyState, Outcome

__all__ = ["ACTION_TYPES", "DEFAULT_REACH", "PITCH_RANGE", "Action", "ActionLimits", "ActionParseError", "Body",
           "BodyState", "Close", "Finish", "Grab", "Interact", "MoveForward", "Open", "Outcome", "Put", "RotateDown",
           "RotateRight", "Speak", "Step", "clip_action", "clip_step", "format_action", "format_actions",
           "parse_actions"]
