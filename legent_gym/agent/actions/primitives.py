"""The action language's primitives: one frozen dataclass per call of the language
(:class:`Speak`, :class:`MoveForward`, ...), the :data:`Action` union, :data:`Step` and
:data:`ACTION_TYPES`. The language itself is described in :mod:`legent_gym.agent.actions`."""

from __future__ import annotations

import math
import numbers
import operator
from dataclasses import dataclass
from typing import SupportsIndex, cast

# --------------------------------------------------------------------------------------
# Value checks shared by the dataclasses. They normalise numpy scalars to Python types so
# that actions compare, hash and print the same whatever produced them (a parser, a
# policy's float32 output, a numpy int64 id).
# --------------------------------------------------------------------------------------


def _finite_float(value: object, what: str) -> float:
    """``value`` as a finite Python float, or ``TypeError`` / ``ValueError``."""
    if type(value) is float and math.isfinite(value):  # the common case, without the ABC check
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{what} must be a real number, got {value!r}")
    result = float(value)
    if not math.isfinite(result):
        raise ValueError(f"{what} must be finite, got {value!r}")
    return result


def _object_id(value: object, what: str) -> int:
    """``value`` as a non-negative Python int (numpy integers accepted, bools not)."""
    if isinstance(value, bool):
        raise TypeError(f"{what} must be an integer object id, got {value!r}")
    try:
        # anything without __index__ raises the TypeError handled here
        result = operator.index(cast(SupportsIndex, value))
    except TypeError:
        raise TypeError(f"{what} must be an integer object id, got {value!r}") from None
    if result < 0:
        raise ValueError(f"{what} must be a non-negative object id, got {result}")
    return result


def _target(value: object, what: str, *, doors: bool) -> int | str | None:
    """A target: None, an object id, or (where ``doors``) a non-empty door id string."""
    if value is None:
        return None
    if isinstance(value, str):
        if not doors:
            raise TypeError(f"{what} takes an object id, not a door id ({value!r})")
        if not value:
            raise ValueError(f"{what}: a door id must not be empty")
        return value
    return _object_id(value, what)


def _set(obj: object, name: str, value: object) -> None:
    # Frozen dataclasses forbid plain assignment; normalising in __post_init__ is the
    # documented exception.
    object.__setattr__(obj, name, value)


# --------------------------------------------------------------------------------------
# The primitives
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Speak:
    """Say ``text`` (to the user; in LEGENT speech also ends the episode)."""

    text: str

    def __post_init__(self) -> None:
        if not isinstance(self.text, str):
            raise TypeError(f"Speak.text must be a str, got {self.text!r}")


@dataclass(frozen=True)
class MoveForward:
    """Walk ``distance`` metres straight ahead (negative values are clipped to 0)."""

    distance: float

    def __post_init__(self) -> None:
        _set(self, "distance", _finite_float(self.distance, "MoveForward.distance"))


@dataclass(frozen=True)
class RotateRight:
    """Turn ``degrees`` about the vertical axis; ``+`` is right, ``-`` is left."""

    degrees: float

    def __post_init__(self) -> None:
        _set(self, "degrees", _finite_float(self.degrees, "RotateRight.degrees"))


@dataclass(frozen=True)
class RotateDown:
    """Tilt the head ``degrees``; ``+`` is down, ``-`` is up (pitch is clamped)."""

    degrees: float

    def __post_init__(self) -> None:
        _set(self, "degrees", _finite_float(self.degrees, "RotateDown.degrees"))


@dataclass(frozen=True)
class Interact:
    """LEGENT's generic toggle: grab / put / open / close, whatever fits the target."""

    target: int | str | None = None

    def __post_init__(self) -> None:
        _set(self, "target", _target(self.target, "Interact.target", doors=True))


@dataclass(frozen=True)
class Grab:
    """Pick up the object at the image centre, or object ``target`` by id."""

    target: int | None = None

    def __post_init__(self) -> None:
        _set(self, "target", _target(self.target, "Grab.target", doors=False))


@dataclass(frozen=True)
class Put:
    """Put the held object at the image centre, or on receptacle ``target`` by id."""

    target: int | None = None

    def __post_init__(self) -> None:
        _set(self, "target", _target(self.target, "Put.target", doors=False))


@dataclass(frozen=True)
class Open:
    """Open what is looked at, object ``target`` (int) or door ``target`` (str)."""

    target: int | str | None = None

    def __post_init__(self) -> None:
        _set(self, "target", _target(self.target, "Open.target", doors=True))


@dataclass(frozen=True)
class Close:
    """Close what is looked at, object ``target`` (int) or door ``target`` (str)."""

    target: int | str | None = None

    def __post_init__(self) -> None:
        _set(self, "target", _target(self.target, "Close.target", doors=True))


@dataclass(frozen=True)
class Finish:
    """Declare the task done."""


# A runtime union: usable in annotations and in isinstance() checks.
Action = (
    Speak | MoveForward | RotateRight | RotateDown | Interact | Grab | Put | Open | Close | Finish
)
Step = tuple[Action, ...]
"""One step: several primitives executed in order (``move_forward(1.8), rotate_right(30)``)."""

ACTION_TYPES: tuple[type, ...] = (
    Speak, MoveForward, RotateRight, RotateDown, Interact, Grab, Put, Open, Close, Finish,
)

