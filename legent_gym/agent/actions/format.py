"""A step -> its canonical action text: :func:`format_action`, :func:`format_actions`,
:func:`format_number` and :func:`quote_string` (``parse_actions(format_actions(step)) ==
step`` for every non-empty step)."""

from __future__ import annotations

import json
from collections.abc import Iterable

from legent_gym.agent.actions.primitives import (
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
)

# The name each dataclass is written as (release() is read but put() is written).
ACTION_NAMES: dict[type, str] = {
    Speak: "speak",
    MoveForward: "move_forward",
    RotateRight: "rotate_right",
    RotateDown: "rotate_down",
    Interact: "interact",
    Grab: "grab",
    Put: "put",
    Open: "open",
    Close: "close",
    Finish: "finish",
}


# --------------------------------------------------------------------------------------
# Printer
# --------------------------------------------------------------------------------------


def format_number(value: float) -> str:
    """Shortest text that reads back as exactly ``float(value)``; ``1.0`` prints as ``1``."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def _format_target(target: int | str | None) -> str:
    if target is None:
        return ""
    if isinstance(target, str):
        return quote_string(target)
    return str(target)


def quote_string(text: str) -> str:
    """``text`` as a quoted string literal of action code (what :class:`Tokenizer` reads back)."""
    # JSON escaping (double quotes, backslash, control characters) keeps unicode as is;
    # the tokenizer reads every escape json.dumps writes.
    return json.dumps(text, ensure_ascii=False)


def format_action(action: Action) -> str:
    """The canonical code of one primitive, e.g. ``move_forward(1.2)``."""
    name = ACTION_NAMES.get(type(action))
    if name is None:
        raise TypeError(f"not an action: {action!r}")
    if isinstance(action, Speak):
        arg = quote_string(action.text)
    elif isinstance(action, MoveForward):
        arg = format_number(action.distance)
    elif isinstance(action, (RotateRight, RotateDown)):
        arg = format_number(action.degrees)
    elif isinstance(action, Finish):
        arg = ""
    else:
        arg = _format_target(action.target)
    return f"{name}({arg})"


def format_actions(step: Iterable[Action]) -> str:
    """The canonical code of a step: primitives joined by ``", "``.

    ``parse_actions(format_actions(step)) == step`` for every non-empty step.

    Raises:
        ValueError: for an empty step (LEGENT's language has no "do nothing").
    """
    parts = [format_action(a) for a in step]
    if not parts:
        raise ValueError("an empty step has no text form (the action language has no no-op)")
    return ", ".join(parts)
