"""Gymnasium spaces for the action language of :mod:`legent_gym.agent.actions`.

Two ways to act, one meaning:

* **Text** (:func:`text_action_space`): the step as code, ``"move_forward(1.8),
  rotate_right(30)"``, parsed with :func:`~legent_gym.agent.actions.parse_actions`. This is
  what language models read and write, and the only form that can address objects by id
  or doors by name.
* **Dict** (:func:`continuous_action_space`): one slot per kind of primitive, for RL
  policies. Keys, in the fixed order in which a step executes them::

      move_forward   Box(0, max_move)                  metres
      rotate_right   Box(-max_rotate_right, +max)      degrees, + is right
      rotate_down    Box(-max_rotate_down, +max)       degrees, + is down
      interact       Discrete(6)                       0 none, 1 interact, 2 grab, 3 put,
                                                       4 open, 5 close (at the image centre)
      speak          Text(0..max_speech_chars)         "" is no speech
      finish         Discrete(2)                       1 is finish()

  A zero / ``0`` / ``""`` means "not this primitive". Moving first and turning after
  matches LEGENT's expert, which joins a move with the turn towards the next corner:
  ``move_forward(1.8), rotate_right(30)``.

:func:`dict_to_actions` and :func:`actions_to_dict` convert between the two, losslessly:
``actions_to_dict(dict_to_actions(d))`` equals ``d`` for every ``d`` in the space, also
with :func:`~legent_gym.agent.actions.format_actions` / ``parse_actions`` in between (except
the no-op dict, whose empty step has no text form). The other way,
``dict_to_actions(actions_to_dict(step)) == step`` for every step the dict can represent:
primitives in the fixed order, each at most once, no ids or door ids, no zero-valued
moves or empty speech (those mean "absent" in the dict) and numbers that are exact in
float32 (others are rounded to the nearest float32, as the Box stores them; pass
``strict=True`` to refuse instead).
"""

from __future__ import annotations

import math
import string
from collections.abc import Callable, Iterable, Mapping
from typing import Any, cast

import numpy as np
from gymnasium import spaces

from legent_gym.agent.actions import (
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
    format_action,
    parse_actions,
)
from legent_gym.envs.text_space import VectorSafeText

__all__ = [
    "DICT_KEYS",
    "INTERACTIONS",
    "SPEECH_CHARSET",
    "TEXT_ACTION_CHARSET",
    "actions_to_dict",
    "continuous_action_space",
    "dict_to_actions",
    "noop_dict",
    "speech_space",
    "text_action_space",
]

# Accented Latin letters common in European-language sentences (Latin-1 letters plus the
# French oe ligature and Y with diaeresis).
_ACCENTED = (
    "ÀÁÂÃÄÅÆÇÈÉÊËÌÍÎÏÑÒÓÔÕÖØÙÚÛÜÝŒŸ"
    "àáâãäåæçèéêëìíîïñòóôõöøùúûüýÿœß"
)
# Typographic quotes, dashes and the ellipsis: language models write these constantly.
_TYPOGRAPHIC = "‘’“”–—…"

SPEECH_CHARSET: str = "".join(sorted(set(
    string.ascii_letters + string.digits + " " + ".,!?'\"-:;()/&%$#@+*=_"
    + _ACCENTED + _TYPOGRAPHIC
)))
"""Characters speech may use in the dict space, as a sorted string.

A sorted ``str`` rather than a set so that ``Text.sample()`` draws the same characters
for the same seed in every process (set order depends on hash randomisation).
"""

TEXT_ACTION_CHARSET: str = "".join(sorted(set(SPEECH_CHARSET + "\\\t\n")))
"""Characters of action code: the grammar (names, numbers, ``(),``, quotes, backslash
escapes, whitespace) plus everything speech may contain."""

DICT_KEYS: tuple[str, ...] = (
    "move_forward", "rotate_right", "rotate_down", "interact", "speak", "finish",
)
"""The dict space's keys, in the order a step executes them."""

INTERACTIONS: tuple[type[Interact | Grab | Put | Open | Close] | None, ...] = (None, Interact, Grab, Put, Open, Close)
"""``interact`` slot value -> primitive (index 0: no interaction)."""

_SPEECH_SET = frozenset(SPEECH_CHARSET)
_SLOT: dict[type, str] = {
    MoveForward: "move_forward",
    RotateRight: "rotate_right",
    RotateDown: "rotate_down",
    Interact: "interact",
    Grab: "interact",
    Put: "interact",
    Open: "interact",
    Close: "interact",
    Speak: "speak",
    Finish: "finish",
}


# --------------------------------------------------------------------------------------
# Spaces
# --------------------------------------------------------------------------------------


def speech_space(max_length: int = 500) -> spaces.Text:
    """What an agent may say: 0..``max_length`` characters of :data:`SPEECH_CHARSET`.

    Built explicitly because Gymnasium's default ``Text`` charset is alphanumeric only
    (no space, no punctuation: not even "It's on the sofa." would fit). A
    :class:`~legent_gym.envs.text_space.VectorSafeText`, so that observations of it come
    back right through Gymnasium's async vector env.
    """
    return VectorSafeText(min_length=0, max_length=max_length, charset=SPEECH_CHARSET)


def text_action_space(max_length: int = 1000) -> spaces.Text:
    """A step as action code (e.g. ``'move_forward(1.2), speak("Hi!")'``).

    Membership only checks length and characters; whether the text is a valid step is
    :func:`~legent_gym.agent.actions.parse_actions`'s business, and its error message is
    what an environment reports back.
    """
    return VectorSafeText(min_length=0, max_length=max_length, charset=TEXT_ACTION_CHARSET)


def continuous_action_space(limits: ActionLimits | None = None) -> spaces.Dict:
    """The dict action space (see the module docstring), bounded by ``limits``."""
    limits = limits or ActionLimits()

    def scalar(low: float, high: float) -> spaces.Box:
        return spaces.Box(low=low, high=high, shape=(), dtype=np.float32)

    slots = {
        "move_forward": scalar(0.0, limits.max_move),
        "rotate_right": scalar(-limits.max_rotate_right, limits.max_rotate_right),
        "rotate_down": scalar(-limits.max_rotate_down, limits.max_rotate_down),
        "interact": spaces.Discrete(len(INTERACTIONS)),
        "speak": speech_space(limits.max_speech_chars),
        "finish": spaces.Discrete(2),
    }
    # sort_keys=False: the key order is the execution order, and it is part of the API.
    return spaces.Dict(slots, sort_keys=False)


def noop_dict() -> dict[str, Any]:
    """The dict meaning "do nothing this step" (every slot absent)."""
    return {
        "move_forward": np.array(0.0, dtype=np.float32),
        "rotate_right": np.array(0.0, dtype=np.float32),
        "rotate_down": np.array(0.0, dtype=np.float32),
        "interact": np.int64(0),
        "speak": "",
        "finish": np.int64(0),
    }


# --------------------------------------------------------------------------------------
# dict -> actions
# --------------------------------------------------------------------------------------


def _scalar(value: Any, key: str) -> Any:
    """The single element of ``value`` (a number, a 0-d or 1-element array)."""
    array = np.asarray(value)
    if array.size != 1:
        raise ValueError(f"{key!r} must be a single value, got shape {array.shape}")
    return array.reshape(()).item()


def _code(value: Any, key: str, n: int) -> int:
    """A Discrete slot's value as an int in ``range(n)``."""
    item = _scalar(value, key)
    if isinstance(item, bool) or not isinstance(item, int):
        if isinstance(item, float) and item.is_integer():
            item = int(item)
        else:
            raise ValueError(f"{key!r} must be an integer in 0..{n - 1}, got {value!r}")
    if not 0 <= item < n:
        raise ValueError(f"{key!r} must be in 0..{n - 1}, got {item}")
    return item


def dict_to_actions(action_dict: Mapping[str, Any]) -> Step:
    """The step a dict action means, primitives in execution order.

    Missing keys mean "absent"; unknown keys raise ``ValueError``. Values are not
    checked against the bounds of a particular space (the environment clips with
    :func:`~legent_gym.agent.actions.clip_action` and reports).
    """
    unknown = sorted(set(action_dict) - set(DICT_KEYS))
    if unknown:
        raise ValueError(f"unknown action keys {unknown}; expected {list(DICT_KEYS)}")
    step: list[Action] = []
    numeric: dict[str, Callable[[float], Action]] = {
        "move_forward": MoveForward, "rotate_right": RotateRight, "rotate_down": RotateDown}
    for key, cls in numeric.items():
        if key in action_dict:
            value = float(_scalar(action_dict[key], key))
            if value != 0.0:  # also drops -0.0
                step.append(cls(value))
    interaction = INTERACTIONS[_code(action_dict.get("interact", 0), "interact", len(INTERACTIONS))]
    if interaction is not None:  # code 0: no interaction
        step.append(interaction())
    speech = action_dict.get("speak", "")
    if not isinstance(speech, str):
        raise ValueError(f"'speak' must be a str, got {type(speech).__name__}")
    if speech:
        step.append(Speak(str(speech)))  # a plain str, even from np.str_
    if _code(action_dict.get("finish", 0), "finish", 2):
        step.append(Finish())
    return tuple(step)


def parse_step(action: Any, action_type: str) -> Step:
    """The primitives of one env action: action code (a ``str``) in either action type, or
    a dict action with ``action_type="continuous"``. Raises
    :class:`~legent_gym.agent.actions.ActionParseError` (bad code, or not a string where
    text is expected) or ``ValueError`` (a bad dict)."""
    if action_type == "text":
        if not isinstance(action, str):
            raise ActionParseError(str(action), 0, f"expected action code as a string, got {type(action).__name__}")
        return parse_actions(action)
    if isinstance(action, str):
        return parse_actions(action)
    return dict_to_actions(action)


# --------------------------------------------------------------------------------------
# actions -> dict
# --------------------------------------------------------------------------------------


def _check_order(step: Iterable[Action]) -> list[tuple[str, Action]]:
    """(slot, action) pairs, after checking each slot is used once, in the fixed order."""
    placed: list[tuple[str, Action]] = []
    for action in step:
        slot = _SLOT.get(type(action))
        if slot is None:
            raise TypeError(f"not an action: {action!r}")
        if placed:
            last_slot, last = placed[-1]
            if slot in (s for s, _ in placed):
                raise ValueError(
                    f"{format_action(action)} cannot be represented: the {slot!r} slot is "
                    f"already used by {format_action(dict(placed)[slot])} (one per step)")
            if DICT_KEYS.index(slot) < DICT_KEYS.index(last_slot):
                raise ValueError(
                    f"{format_action(action)} after {format_action(last)} cannot be "
                    f"represented: the dict executes in the order {', '.join(DICT_KEYS)}")
        placed.append((slot, action))
    return placed


def _float32(value: float, action: Action, *, strict: bool) -> np.ndarray:
    """``value`` as a 0-d float32 array, refusing values the dict would lose."""
    what = format_action(action)
    if value == 0.0:
        raise ValueError(f"{what} cannot be represented: 0 means 'absent' in the dict")
    stored = np.float32(value)
    if not math.isfinite(float(stored)) or stored == 0.0:
        raise ValueError(f"{what} cannot be represented: out of float32 range")
    if strict and float(stored) != value:
        raise ValueError(f"{what} is not exact in float32 (would become {float(stored)!r})")
    return np.array(stored, dtype=np.float32)


def _check_bound(stored: np.ndarray, box: spaces.Box, action: Action) -> None:
    if not box.contains(stored):
        raise ValueError(
            f"{format_action(action)} is outside [{float(box.low)!r}, {float(box.high)!r}]; "
            "clip it first (legent_gym.agent.actions.clip_action)")


def _check_speech(action: Speak, space: spaces.Text | None) -> None:
    if not action.text:
        raise ValueError("speak(\"\") cannot be represented: \"\" means 'absent' in the dict")
    bad = sorted(set(action.text) - _SPEECH_SET)
    if bad:
        raise ValueError(
            f"speech contains characters outside SPEECH_CHARSET: {''.join(bad)!r}")
    if space is not None and not space.contains(action.text):
        raise ValueError(
            f"speech of {len(action.text)} characters is longer than {space.max_length}")


def _interaction_code(action: Action) -> int:
    target = getattr(action, "target", None)
    if isinstance(target, str):
        raise ValueError(
            f"{format_action(action)} cannot be represented: the dict has no door ids")
    if target is not None:
        raise ValueError(
            f"{format_action(action)} cannot be represented: the dict has no object ids "
            "(it acts on what the image centre shows)")
    return INTERACTIONS.index(type(action))


def actions_to_dict(
    step: Iterable[Action], *, limits: ActionLimits | None = None, strict: bool = False
) -> dict[str, Any]:
    """The dict action for ``step``; ``ValueError`` naming the problem if it has none.

    Args:
        step: primitives in execution order.
        limits: when given, values must also lie inside ``continuous_action_space(limits)``
            (moves and turns within their bounds, speech short enough).
        strict: refuse numbers that float32 cannot hold exactly (by default they are
            rounded to the nearest float32, as the Box would store them).
    """
    space = continuous_action_space(limits) if limits is not None else None
    out = noop_dict()
    for slot, action in _check_order(step):
        # each primitive type has exactly one slot (_check_order looks it up by exact type)
        if isinstance(action, (MoveForward, RotateRight, RotateDown)):  # the numeric slots
            value = action.distance if isinstance(action, MoveForward) else action.degrees
            if isinstance(action, MoveForward) and value < 0:
                raise ValueError(
                    f"{format_action(action)} cannot be represented: no walking backwards")
            stored = _float32(value, action, strict=strict)
            if space is not None:
                _check_bound(stored, cast(spaces.Box, space[slot]), action)
            out[slot] = stored
        elif slot == "interact":
            out[slot] = np.int64(_interaction_code(action))
        elif isinstance(action, Speak):  # slot "speak"
            _check_speech(action, cast(spaces.Text, space["speak"]) if space is not None else None)
            out[slot] = action.text
        else:  # finish
            out[slot] = np.int64(1)
    return out
