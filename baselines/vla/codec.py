"""Action text <-> what the model predicts: a template, binned numbers and a speech class.

The model writes action code (``move_forward(1.87), rotate_right(-47.9)``) through a
hybrid decoder rather than character by character: a classifier picks the *template* (the
step with its numbers and speech left as slots, ``move_forward(#), rotate_right(#)``), one
head per numeric slot picks a bin of the primitive's range plus an offset inside the bin,
and a classifier over the training data's sentences fills ``speak(@)``. The result is
formatted with :func:`~legent_gym.agent.actions.format_actions` and re-read with
:func:`~legent_gym.agent.actions.parse_actions`, so every output is valid code.

Why bins and not a regression: the expert's numbers are multi-modal where the image is
ambiguous (with the user out of sight it turns +90 or -90 degrees, by privileged
knowledge); a mean-squared regression would average the two into "turn 0", a classifier
picks one mode. The offset keeps the precision of a regression inside the chosen bin.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from legent_gym.agent.actions import (
    ActionLimits,
    ActionParseError,
    MoveForward,
    RotateDown,
    RotateRight,
    Speak,
    format_action,
    format_actions,
    parse_actions,
)

#: The numeric primitives, their text name, the decimals the expert writes and the field.
NUMERIC = {
    MoveForward: ("move_forward", 2, "distance"),
    RotateRight: ("rotate_right", 1, "degrees"),
    RotateDown: ("rotate_down", 1, "degrees"),
}
NUMBER_SLOT = "#"
SPEECH_SLOT = "@"
UNKNOWN = "<unk>"


def numeric_range(name: str, limits: ActionLimits) -> tuple[float, float]:
    """The values a primitive can take under ``limits`` (the env clips anything else)."""
    if name == "move_forward":
        return 0.0, float(limits.max_move)
    if name == "rotate_right":
        return -float(limits.max_rotate_right), float(limits.max_rotate_right)
    if name == "rotate_down":
        return -float(limits.max_rotate_down), float(limits.max_rotate_down)
    raise KeyError(f"not a numeric primitive: {name!r}")


@dataclass(frozen=True)
class Decomposed:
    """One step as the model sees it: the template, the value of each numeric slot (keyed
    ``name:occurrence``, e.g. ``rotate_right:0``) and the spoken text, if any."""

    template: str
    numbers: dict[str, float]
    speech: str | None


def decompose(text: str) -> Decomposed:
    """Split action code into a template and its slot values.

    >>> decompose('move_forward(1.5), rotate_right(-30)')
    Decomposed(template='move_forward(#), rotate_right(#)', numbers={'move_forward:0': 1.5, 'rotate_right:0': -30.0}, speech=None)

    Raises ``ActionParseError`` for text that is not a valid step, and ``ValueError`` for a
    step that speaks twice (one speech slot per step).
    """
    step = parse_actions(text)
    parts, numbers, speech, seen = [], {}, None, Counter()
    for action in step:
        spec = NUMERIC.get(type(action))
        if spec is not None:
            name, _, field = spec
            numbers[f"{name}:{seen[name]}"] = float(getattr(action, field))
            seen[name] += 1
            parts.append(f"{name}({NUMBER_SLOT})")
        elif isinstance(action, Speak):
            if speech is not None:
                raise ValueError(f"a step may speak once, got {text!r}")
            speech = action.text
            parts.append(f"speak({SPEECH_SLOT})")
        else:  # no argument, or an id that is part of the template (grab(3))
            parts.append(format_action(action))
    return Decomposed(", ".join(parts), numbers, speech)


def _slot_names(template: str) -> list[str]:
    """The numeric slot keys of a template, in order (``["move_forward:0", ...]``)."""
    names, seen = [], Counter()
    for part in template.split(", "):
        if part.endswith(f"({NUMBER_SLOT})"):
            name = part[: -len(NUMBER_SLOT) - 2]
            names.append(f"{name}:{seen[name]}")
            seen[name] += 1
    return names


class ActionCodec:
    """The vocabularies of one training set: templates, numeric slots and sentences.

    ``bins`` numeric bins per slot cover the primitive's range under ``limits``; the bin
    centres include both ends (so ``move_forward(2)`` and ``rotate_right(90)``, the
    expert's most common values, are exact).
    """

    def __init__(self, templates: Sequence[str], slots: Sequence[str], speeches: Sequence[str],
                 bins: int = 37, limits: ActionLimits | None = None):
        if bins < 2:
            raise ValueError(f"bins must be >= 2, got {bins}")
        self.templates = [UNKNOWN, *templates]   # id 0: a history action the codec never saw
        self.slots = list(slots)
        self.speeches = [UNKNOWN, *speeches]
        self.bins = int(bins)
        self.limits = limits or ActionLimits()
        self._template_id = {t: i for i, t in enumerate(self.templates)}
        self._speech_id = {s: i for i, s in enumerate(self.speeches)}
        self._slot_id = {s: i for i, s in enumerate(self.slots)}
        for template in templates:
            missing = [s for s in _slot_names(template) if s not in self._slot_id]
            if missing:
                raise ValueError(f"template {template!r} has slots {missing} not in slots {self.slots}")

    # -- building -------------------------------------------------------------------------
    @classmethod
    def fit(cls, actions: Iterable[str], bins: int = 37, limits: ActionLimits | None = None) -> ActionCodec:
        """The codec of a set of action texts (sorted vocabularies: the same data gives the
        same ids)."""
        templates, slots, speeches = set(), set(), set()
        for text in actions:
            d = decompose(text)
            templates.add(d.template)
            slots.update(d.numbers)
            if d.speech is not None:
                speeches.add(d.speech)
        if not templates:
            raise ValueError("no actions to build a codec from")
        return cls(sorted(templates), sorted(slots), sorted(speeches), bins, limits)

    def to_dict(self) -> dict:
        return {"templates": self.templates[1:], "slots": self.slots, "speeches": self.speeches[1:],
                "bins": self.bins, "limits": {
                    "max_move": self.limits.max_move, "max_rotate_right": self.limits.max_rotate_right,
                    "max_rotate_down": self.limits.max_rotate_down,
                    "pitch_range": list(self.limits.pitch_range),
                    "max_speech_chars": self.limits.max_speech_chars}}

    @classmethod
    def from_dict(cls, data: dict) -> ActionCodec:
        limits = dict(data["limits"])
        limits["pitch_range"] = tuple(limits["pitch_range"])
        return cls(data["templates"], data["slots"], data["speeches"], data["bins"], ActionLimits(**limits))

    # -- numbers <-> bins -------------------------------------------------------------------
    def _range(self, slot: str) -> tuple[float, float]:
        return numeric_range(slot.split(":")[0], self.limits)

    def bin_width(self, slot: str) -> float:
        low, high = self._range(slot)
        return (high - low) / (self.bins - 1)

    def to_bin(self, slot: str, value: float) -> tuple[int, float]:
        """The bin of ``value`` (clipped to the range) and the offset from the bin's centre,
        in bin widths (in ``[-0.5, 0.5]``)."""
        low, high = self._range(slot)
        width = self.bin_width(slot)
        value = min(max(value, low), high)
        index = min(max(round((value - low) / width), 0), self.bins - 1)
        return index, (value - (low + index * width)) / width

    def from_bin(self, slot: str, index: int, offset: float) -> float:
        low, high = self._range(slot)
        width = self.bin_width(slot)
        offset = min(max(offset, -0.5), 0.5)
        return min(max(low + (index + offset) * width, low), high)

    def normalise(self, slot: str, value: float) -> float:
        """``value`` scaled to about ``[-1, 1]`` (an input feature for history actions)."""
        low, high = self._range(slot)
        return 2.0 * (value - low) / (high - low) - 1.0

    # -- ids --------------------------------------------------------------------------------
    @property
    def n_templates(self) -> int:
        return len(self.templates)

    @property
    def n_speeches(self) -> int:
        return len(self.speeches)

    def template_id(self, template: str) -> int:
        return self._template_id.get(template, 0)

    def speech_id(self, speech: str | None) -> int:
        """0 for no speech or a sentence outside the vocabulary."""
        return 0 if speech is None else self._speech_id.get(speech, 0)

    def slot_id(self, slot: str) -> int | None:
        return self._slot_id.get(slot)

    @staticmethod
    def encode(text: str) -> Decomposed | None:
        """``decompose(text)``, or None for text that does not parse (a no-op in the env)."""
        try:
            return decompose(text)
        except (ActionParseError, ValueError):
            return None

    # -- writing ----------------------------------------------------------------------------
    def format(self, template_id: int, numbers: dict[str, float], speech_id: int) -> str:
        """Action code for a template filled with slot values and a sentence.

        Numbers are rounded as the expert writes them (2 decimals for metres, 1 for
        degrees); the text is checked with ``parse_actions``. Raises ``ValueError`` for the
        unknown template (id 0) or a missing slot value."""
        if not 0 < template_id < len(self.templates):
            raise ValueError(f"template id {template_id} is not a known template (1..{len(self.templates) - 1})")
        template = self.templates[template_id]
        parts, seen = [], Counter()
        for part in template.split(", "):
            if part.endswith(f"({NUMBER_SLOT})"):
                name = part[: -len(NUMBER_SLOT) - 2]
                key = f"{name}:{seen[name]}"
                seen[name] += 1
                if key not in numbers:
                    raise ValueError(f"no value for slot {key} of template {template!r}")
                decimals = next(spec[1] for spec in NUMERIC.values() if spec[0] == name)
                value = round(float(numbers[key]), decimals) + 0.0  # + 0.0: no "-0"
                parts.append(f"{name}({value!r})")
            elif part == f"speak({SPEECH_SLOT})":
                sentence = self.speeches[speech_id] if 0 < speech_id < len(self.speeches) else ""
                parts.append(format_action(Speak(sentence)))
            else:
                parts.append(part)
        # Round-trip through the parser: the canonical text, and proof that it is valid.
        return format_actions(parse_actions(", ".join(parts)))

    def template_slots(self, template_id: int) -> list[str]:
        return _slot_names(self.templates[template_id]) if template_id else []
