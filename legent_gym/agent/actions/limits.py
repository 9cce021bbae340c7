"""What one primitive may do: :class:`ActionLimits`, and :func:`clip_action` /
:func:`clip_step`, which clip to them and say what changed."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import overload

from legent_gym.agent.actions.format import ACTION_NAMES, format_action
from legent_gym.agent.actions.primitives import (
    Action,
    MoveForward,
    RotateDown,
    RotateRight,
    Speak,
    Step,
)

# --------------------------------------------------------------------------------------
# Limits and clipping
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ActionLimits:
    """What one primitive may do; LEGENT's values by default.

    Attributes:
        max_move: metres per ``move_forward``.
        max_rotate_right: degrees per ``rotate_right``, either way.
        max_rotate_down: degrees per ``rotate_down``, either way.
        pitch_range: (min, max) head pitch in degrees, ``+`` is down; the pitch is
            clamped to this range (a ``rotate_down`` that would leave it is shortened).
        max_speech_chars: characters per ``speak``; longer speech is truncated.
    """

    max_move: float = 2.0
    max_rotate_right: float = 90.0
    max_rotate_down: float = 90.0
    pitch_range: tuple[float, float] = (-60.0, 60.0)
    max_speech_chars: int = 500

    def __post_init__(self) -> None:
        low, high = self.pitch_range
        if not (self.max_move >= 0 and self.max_rotate_right >= 0 and self.max_rotate_down >= 0):
            raise ValueError(f"limits must be non-negative: {self}")
        if not low <= high:
            raise ValueError(f"pitch_range must be (min, max), got {self.pitch_range}")
        if self.max_speech_chars < 0:
            raise ValueError(f"max_speech_chars must be non-negative, got {self.max_speech_chars}")


def _clip_move(action: MoveForward, limits: ActionLimits) -> tuple[Action, str | None]:
    d = action.distance
    if d < 0:
        return MoveForward(0.0), f"{format_action(action)} clipped to 0 m (no walking backwards)"
    if d > limits.max_move:
        return (MoveForward(limits.max_move),
                f"{format_action(action)} clipped to {float(limits.max_move)!r} m")
    return action, None


def _clip_turn(action: RotateRight, limits: ActionLimits) -> tuple[Action, str | None]:
    bound = limits.max_rotate_right
    clipped = min(max(action.degrees, -bound), bound)
    if clipped == action.degrees:
        return action, None
    return RotateRight(clipped), f"{format_action(action)} clipped to {clipped!r} degrees"


def _clip_tilt(
    action: RotateDown, limits: ActionLimits, pitch: float | None
) -> tuple[Action, str | None]:
    bound = limits.max_rotate_down
    clipped = min(max(action.degrees, -bound), bound)
    why = ""
    if pitch is not None:
        # Shorten the tilt so the head does not leave pitch_range. Only shorten: never
        # lengthen it or flip its sign (a head already outside the range may move back).
        low, high = limits.pitch_range
        if clipped > 0 and pitch + clipped > high:
            clipped = max(high - pitch, 0.0)
            why = f" (pitch limited to {float(low)!r}..{float(high)!r} degrees)"
        elif clipped < 0 and pitch + clipped < low:
            clipped = min(low - pitch, 0.0)
            why = f" (pitch limited to {float(low)!r}..{float(high)!r} degrees)"
    if clipped == action.degrees:
        return action, None
    return RotateDown(clipped), f"{format_action(action)} clipped to {clipped!r} degrees{why}"


def _clip_speech(action: Speak, limits: ActionLimits) -> tuple[Action, str | None]:
    n = len(action.text)
    if n <= limits.max_speech_chars:
        return action, None
    return (Speak(action.text[:limits.max_speech_chars]),
            f"speech of {n} characters truncated to {limits.max_speech_chars}")


@overload
def clip_action(
    action: Speak, limits: ActionLimits, *, pitch: float | None = None
) -> tuple[Speak, str | None]: ...


@overload
def clip_action(
    action: Action, limits: ActionLimits, *, pitch: float | None = None
) -> tuple[Action, str | None]: ...


def clip_action(
    action: Action, limits: ActionLimits, *, pitch: float | None = None
) -> tuple[Action, str | None]:
    """Clip one primitive to ``limits``; return it and a note saying what changed (or None).

    ``pitch`` (degrees, ``+`` down) is the head's current pitch; when given, a
    ``rotate_down`` is also shortened so the pitch stays within ``limits.pitch_range``.

    >>> clip_action(MoveForward(3.5), ActionLimits())
    (MoveForward(distance=2.0), 'move_forward(3.5) clipped to 2.0 m')
    """
    # exact types, as everywhere in this module
    if type(action) is MoveForward:
        return _clip_move(action, limits)
    if type(action) is RotateRight:
        return _clip_turn(action, limits)
    if type(action) is RotateDown:
        return _clip_tilt(action, limits, pitch)
    if type(action) is Speak:
        return _clip_speech(action, limits)
    if type(action) not in ACTION_NAMES:
        raise TypeError(f"not an action: {action!r}")
    return action, None


def clip_step(
    step: Iterable[Action], limits: ActionLimits, *, pitch: float | None = None
) -> tuple[Step, tuple[str, ...]]:
    """Clip every primitive of a step; the pitch is tracked across several ``rotate_down``.

    Returns the clipped step and the notes (one per clipped primitive, in order).
    """
    out: list[Action] = []
    notes: list[str] = []
    for action in step:
        clipped, note = clip_action(action, limits, pitch=pitch)
        if pitch is not None and isinstance(clipped, RotateDown):
            pitch += clipped.degrees
        out.append(clipped)
        if note is not None:
            notes.append(note)
    return tuple(out), tuple(notes)

