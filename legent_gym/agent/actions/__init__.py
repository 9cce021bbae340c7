"""The agent's action language: LEGENT's "actions as code", parsed, printed and clipped.

A model reads and writes actions as short code, several primitives per step, joined by
``", "`` and executed in order::

    move_forward(1.8), rotate_right(30)
    speak("It's on the sofa.")
    grab(), rotate_down(-10)

Primitives (one frozen dataclass each):

========================  ===================================================================
``speak("...")``          say something (in LEGENT any speech also ends the episode)
``move_forward(m)``       walk ``m`` metres straight ahead (``m >= 0``; no walking backwards)
``rotate_right(d)``       turn ``d`` degrees, ``+`` is right, ``-`` is left
``rotate_down(d)``        tilt the head ``d`` degrees, ``+`` is down, ``-`` is up
``interact([target])``    LEGENT's generic toggle: grab, put, open or close what is looked at
``grab([id])``            pick up the object looked at, or object ``id``
``put([id])``             put the held object where the agent looks, or on receptacle ``id``
``release([id])``         LEGENT's name for ``put`` (read, never written)
``open([target])``        open what is looked at, an object ``id`` (a wardrobe) or a door id
``close([target])``       the reverse of ``open``
``finish()``              declare the task done
========================  ===================================================================

Targets: an ``int`` is an object id (non-negative), a ``str`` a door id such as
``"inner"`` (written quoted or as a bare name: ``open(inner)``); no target means "what
the camera's image centre points at", as in LEGENT.

The text form is canonical both ways: ``parse_actions(format_actions(step)) == step``
for every non-empty step. The parser is a hand-written tokenizer plus a recursive-descent
parser (never ``eval``): model output is untrusted text, and every error says what is
wrong and at which character, so the message can be fed back to the model.

Limits (how far one move may go, ...) are not the parser's business; the environment
clips with :func:`clip_action` and reports the note it returns.

The modules, each importing only those above it; every name is re-exported here:

* :mod:`~legent_gym.agent.actions.primitives`: the dataclasses, :data:`Action`, :data:`Step`;
* :mod:`~legent_gym.agent.actions.parse`: :func:`parse_actions`, :class:`Tokenizer`,
  :class:`ActionParseError`;
* :mod:`~legent_gym.agent.actions.format`: :func:`format_actions` and the literals it writes;
* :mod:`~legent_gym.agent.actions.limits`: :class:`ActionLimits`, :func:`clip_action`,
  :func:`clip_step`.
"""

from legent_gym.agent.actions.format import (
    format_action,
    format_actions,
    format_number,
    quote_string,
)
from legent_gym.agent.actions.limits import ActionLimits, clip_action, clip_step
from legent_gym.agent.actions.parse import ActionParseError, Token, Tokenizer, parse_actions
from legent_gym.agent.actions.primitives import (
    ACTION_TYPES,
    Action,
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
)

__all__ = [
    "ACTION_TYPES",
    "Action",
    "ActionLimits",
    "ActionParseError",
    "Close",
    "Finish",
    "Grab",
    "Interact",
    "MoveForward",
    "Open",
    "Put",
    "RotateDown",
    "RotateRight",
    "Speak",
    "Step",
    "Token",
    "Tokenizer",
    "clip_action",
    "clip_step",
    "format_action",
    "format_actions",
    "format_number",
    "parse_actions",
    "quote_string",
]

