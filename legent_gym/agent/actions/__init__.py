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
"""

from __future__ import annotations

import difflib
import functools
import json
import math
import numbers
import operator
import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import SupportsIndex, cast, overload

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


# --------------------------------------------------------------------------------------
# The text form: names and argument kinds
# --------------------------------------------------------------------------------------

# Argument kinds of the grammar's calls.
_STRING = "string"  # speak: a quoted string, required
_NUMBER = "number"  # moves and turns: a finite number, required
_OBJECT = "object"  # grab / put: optional non-negative integer id
_TARGET = "target"  # interact / open / close: optional id or door id (string or name)
_NONE = "none"  # finish: no argument

# name -> (dataclass, argument kind, what the number means). Order is the order shown
# in "known: ..." messages.
_CALLS: dict[str, tuple[type, str, str]] = {
    "speak": (Speak, _STRING, ""),
    "move_forward": (MoveForward, _NUMBER, "metres"),
    "rotate_right": (RotateRight, _NUMBER, "degrees"),
    "rotate_down": (RotateDown, _NUMBER, "degrees"),
    "interact": (Interact, _TARGET, ""),
    "grab": (Grab, _OBJECT, ""),
    "put": (Put, _OBJECT, ""),
    "release": (Put, _OBJECT, ""),  # LEGENT's name; its own parser could not read it
    "open": (Open, _TARGET, ""),
    "close": (Close, _TARGET, ""),
    "finish": (Finish, _NONE, ""),
}

# The name each dataclass is written as (release() is read but put() is written).
_NAMES: dict[type, str] = {
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

# Bare names that Python's float() would read as numbers; here they are errors wherever
# they appear as an argument, so `move_forward(inf)` never walks to infinity and a door
# called "inf" must be quoted.
_NON_FINITE_NAMES = frozenset({"nan", "inf", "infinity"})


class ActionParseError(ValueError):
    """Action text that is not a valid step.

    Attributes:
        text: the whole text that was parsed.
        position: 0-based character index where the problem is.
        reason: what is wrong, without the position (e.g. ``"unknown action 'jump'"``).
    """

    def __init__(self, text: str, position: int, reason: str, message: str | None = None):
        self.text = text
        self.position = position
        self.reason = reason
        self.message = message if message is not None else f"{reason} at position {position}"
        super().__init__(self.message)

    def __reduce__(self):
        # The default reduce would call cls(message) and fail; errors must survive pickling
        # to cross process boundaries (vector envs, pytest-xdist).
        return (type(self), (self.text, self.position, self.reason, self.message))


# --------------------------------------------------------------------------------------
# Tokenizer
# --------------------------------------------------------------------------------------

_NAME_START = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_")
_NAME_CHARS = _NAME_START | frozenset("0123456789")
_DIGITS = frozenset("0123456789")  # ASCII only: str.isdigit() accepts '²', float() does not
_PUNCT = {"(": "LPAREN", ")": "RPAREN", ",": "COMMA"}
_SIMPLE_ESCAPES = {'"': '"', "'": "'", "\\": "\\", "/": "/", "n": "\n", "t": "\t",
                   "r": "\r", "b": "\b", "f": "\f"}


@dataclass(frozen=True)
class Token:
    """One lexeme of action code."""

    kind: str  # NAME, NUMBER, STRING, LPAREN, RPAREN, COMMA, END
    value: str  # the name, the number's text, or the decoded string
    pos: int
    raw: str  # the source text, for "found ..." in messages

    def describe(self) -> str:
        if self.kind == "END":
            return "end of input"
        raw = self.raw if len(self.raw) <= 20 else self.raw[:17] + "..."
        return repr(raw)


class Tokenizer:
    """Splits action text into tokens; raises ActionParseError on malformed lexemes.

    Public because the experts' intermediate-code parser (``experts/program.py``) reads the
    same lexemes (names, numbers, quoted strings with the same escapes)."""

    def __init__(self, text: str):
        self.text = text
        self.i = 0

    def error(self, position: int, reason: str, message: str | None = None) -> ActionParseError:
        return ActionParseError(self.text, position, reason, message)

    def tokens(self) -> list[Token]:
        out: list[Token] = []
        while True:
            tok = self.next_token()
            out.append(tok)
            if tok.kind == "END":
                return out

    def next_token(self) -> Token:
        text, n = self.text, len(self.text)
        while self.i < n and text[self.i].isspace():
            self.i += 1
        start = self.i
        if start >= n:
            return Token("END", "", start, "")
        ch = text[start]
        if ch in _PUNCT:
            self.i += 1
            return Token(_PUNCT[ch], ch, start, ch)
        if ch in _NAME_START:
            return self.name()
        if ch in "\"'":
            return self.string()
        if ch in _DIGITS or ch == "." or ch in "+-":
            return self.number()
        raise self.error(start, f"unexpected character {ch!r}")

    def name(self) -> Token:
        start = self.i
        while self.i < len(self.text) and self.text[self.i] in _NAME_CHARS:
            self.i += 1
        word = self.text[start:self.i]
        return Token("NAME", word, start, word)

    def digits(self) -> int:
        """Consume ASCII digits; return how many."""
        start = self.i
        while self.i < len(self.text) and self.text[self.i] in _DIGITS:
            self.i += 1
        return self.i - start

    def number(self) -> Token:
        """``[+-]? (digits ['.' digits] | '.' digits) [(e|E) [+-]? digits]``."""
        text, start = self.text, self.i
        if text[self.i] in "+-":
            self.i += 1
            # "-inf" / "+nan": name the real problem rather than "unexpected '-'".
            if self.i < len(text) and text[self.i] in _NAME_START:
                word = self.name().value
                if word.lower() in _NON_FINITE_NAMES:
                    raw = text[start:self.i]
                    raise self.error(start, f"non-finite number {raw!r}")
                raise self.error(start, f"unexpected character {text[start]!r}")
        int_digits = self.digits()
        frac_digits = 0
        if self.i < len(text) and text[self.i] == ".":
            self.i += 1
            frac_digits = self.digits()
        if int_digits == 0 and frac_digits == 0:
            raise self.error(start, f"malformed number {text[start:self.i]!r}")
        if self.i < len(text) and text[self.i] in "eE":
            mark = self.i
            self.i += 1
            if self.i < len(text) and text[self.i] in "+-":
                self.i += 1
            if self.digits() == 0:
                raise self.error(mark, f"malformed exponent in number {text[start:self.i]!r}")
        raw = text[start:self.i]
        return Token("NUMBER", raw, start, raw)

    def string(self) -> Token:
        text, start = self.text, self.i
        quote = text[start]
        self.i += 1
        parts: list[str] = []
        while True:
            if self.i >= len(text):
                raise self.error(start, "unterminated string",
                                 f"unterminated string starting at position {start}")
            ch = text[self.i]
            if ch == quote:
                self.i += 1
                return Token("STRING", "".join(parts), start, text[start:self.i])
            if ch == "\\":
                parts.append(self.escape())
            else:
                parts.append(ch)
                self.i += 1

    def escape(self) -> str:
        """Decode the escape at ``self.i`` (a backslash); JSON's set plus ``\\'``."""
        text, at = self.text, self.i
        if at + 1 >= len(text):
            raise self.error(at, "unterminated escape sequence")
        code = text[at + 1]
        if code in _SIMPLE_ESCAPES:
            self.i += 2
            return _SIMPLE_ESCAPES[code]
        if code != "u":
            raise self.error(at, f"unknown escape sequence {text[at:at + 2]!r}")
        value = self.hex4(at)
        # A UTF-16 surrogate pair written as two escapes (as JSON does) is one character.
        if 0xD800 <= value < 0xDC00 and text.startswith("\\u", self.i):
            low = self.peek_hex4(self.i)
            if low is not None and 0xDC00 <= low < 0xE000:
                self.i += 6
                return chr(0x10000 + ((value - 0xD800) << 10) + (low - 0xDC00))
        return chr(value)

    def peek_hex4(self, at: int) -> int | None:
        """The value of ``\\uXXXX`` at ``at``, or None if malformed."""
        digits = self.text[at + 2:at + 6]
        if len(digits) == 4 and all(c in "0123456789abcdefABCDEF" for c in digits):
            return int(digits, 16)
        return None

    def hex4(self, at: int) -> int:
        value = self.peek_hex4(at)
        if value is None:
            raise self.error(at, "\\u escape needs 4 hex digits")
        self.i = at + 6
        return value


# --------------------------------------------------------------------------------------
# Parser (recursive descent over the token list)
# --------------------------------------------------------------------------------------


class _Parser:
    """``step := call ("," call)* [","]``; ``call := NAME "(" [arg] ")"``."""

    def __init__(self, text: str):
        self.text = text
        self.tokens = Tokenizer(text).tokens()
        self.k = 0

    @property
    def tok(self) -> Token:
        return self.tokens[self.k]

    def advance(self) -> Token:
        tok = self.tokens[self.k]
        self.k += 1
        return tok

    def error(self, position: int, reason: str, message: str | None = None) -> ActionParseError:
        return ActionParseError(self.text, position, reason, message)

    def bad(self, tok: Token, reason: str) -> ActionParseError:
        """An error at ``tok`` that also shows what was found there (unless just ')')."""
        found = "" if tok.kind == "RPAREN" else f", found {tok.describe()}"
        return self.error(tok.pos, reason, f"{reason} at position {tok.pos}{found}")

    def expected(self, what: str) -> ActionParseError:
        tok = self.tok
        return self.error(
            tok.pos, f"expected {what}",
            f"expected {what} at position {tok.pos}, found {tok.describe()}",
        )

    def step(self) -> Step:
        if self.tok.kind == "END":
            raise self.error(self.tok.pos, "empty action")
        actions = [self.call()]
        while self.tok.kind == "COMMA":
            self.advance()
            if self.tok.kind == "END":  # a trailing comma is allowed
                break
            actions.append(self.call())
        if self.tok.kind != "END":
            raise self.expected("',' or end of input")
        return tuple(actions)

    def call(self) -> Action:
        tok = self.tok
        if tok.kind != "NAME":
            raise self.expected("an action name")
        if tok.value not in _CALLS:
            raise self.unknown(tok)
        self.advance()
        if self.tok.kind != "LPAREN":
            raise self.expected(f"'(' after {tok.value}")
        self.advance()
        cls, kind, unit = _CALLS[tok.value]
        arg = self.argument(tok.value, kind, unit)
        if self.tok.kind == "COMMA":
            raise self.error(self.tok.pos, f"{tok.value}() takes at most one argument")
        if self.tok.kind != "RPAREN":
            raise self.expected("')'")
        self.advance()
        return cls() if arg is _ABSENT else cls(arg)

    def unknown(self, tok: Token) -> ActionParseError:
        known = ", ".join(_CALLS)
        close = difflib.get_close_matches(tok.value.lower(), _CALLS, n=1)
        hint = f" (did you mean {close[0]}?)" if close else ""
        reason = f"unknown action {tok.value!r}"
        return self.error(tok.pos, reason, f"{reason} at position {tok.pos}{hint}; known: {known}")

    def argument(self, name: str, kind: str, unit: str) -> object:
        """Parse the (optional) argument of ``name``; ``_ABSENT`` if there is none."""
        tok = self.tok
        self.reject_non_finite(tok)
        if kind == _NONE:
            if tok.kind != "RPAREN":
                raise self.bad(tok, f"{name}() takes no argument")
            return _ABSENT
        if kind == _STRING:
            if tok.kind != "STRING":
                raise self.bad(tok, f"{name}() needs a quoted string")
            return self.advance().value
        if kind == _NUMBER:
            if tok.kind != "NUMBER":
                raise self.bad(tok, f"{name}() needs a number ({unit})")
            return self.finite(self.advance())
        # _OBJECT or _TARGET: optional
        if tok.kind == "RPAREN":
            return _ABSENT
        if tok.kind == "NUMBER":
            return self.object_id(name, self.advance())
        if kind == _TARGET and tok.kind in ("STRING", "NAME"):
            return self.door_id(name, self.advance())
        if kind == _TARGET:
            raise self.bad(tok, f"{name}() takes an object id or a door id")
        raise self.bad(tok, f"{name}() takes an object id (a non-negative integer)")

    def reject_non_finite(self, tok: Token) -> None:
        if tok.kind == "NAME" and tok.value.lower() in _NON_FINITE_NAMES:
            raise self.error(tok.pos, f"non-finite number {tok.value!r}")

    def finite(self, tok: Token) -> float:
        value = float(tok.value)  # the tokenizer only lets float()-readable text through
        if not math.isfinite(value):
            raise self.error(tok.pos, f"non-finite number {tok.value!r}")
        return value

    def object_id(self, name: str, tok: Token) -> int:
        if any(c in tok.value for c in ".eE"):
            raise self.bad(tok, f"{name}() needs an integer object id")
        try:
            value = int(tok.value)
        except ValueError:  # longer than sys.get_int_max_str_digits()
            raise self.error(tok.pos, f"{name}() object id is too large") from None
        if value < 0:
            raise self.bad(tok, f"{name}() needs a non-negative object id")
        return value

    def door_id(self, name: str, tok: Token) -> str:
        if not tok.value:
            raise self.error(tok.pos, f"{name}() door id must not be empty")
        return tok.value


_ABSENT = object()  # "no argument", distinct from an argument whose value is None


def parse_actions(text: str) -> Step:
    """Parse one step of action code into a tuple of primitives, in execution order.

    >>> parse_actions("move_forward(1.2), rotate_right(-35)")
    (MoveForward(distance=1.2), RotateRight(degrees=-35.0))

    Raises:
        ActionParseError: with the position and reason, if ``text`` is not a valid step.
        TypeError: if ``text`` is not a ``str``.
    """
    if not isinstance(text, str):
        raise TypeError(f"parse_actions() needs a str, got {type(text).__name__}")
    return _parse_cached(text)


@functools.lru_cache(maxsize=4096)
def _parse_cached(text: str) -> Step:
    # Steps are immutable tuples of frozen dataclasses, so a cached one can be shared;
    # policies and experts repeat the same strings ("move_forward(0.5)") a lot.
    step = _parse_simple(text)
    return step if step is not None else _Parser(text).step()


# The common shapes of a call, read with one regular expression: a known name, plain
# spaces, and a number, a quoted string without escapes, or nothing in the parentheses,
# followed by a comma or the end. Anything else (and anything this path is unsure of)
# goes to the full parser, which gives the same result or the precise error.
_SIMPLE_NUMBER = r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
_SIMPLE_CALL = re.compile(
    r" *([a-z_]+) *\( *(?:(" + _SIMPLE_NUMBER + r")|\"([^\"\\]*)\"|'([^'\\]*)')? *\) *(?:,|\Z)")


def _parse_simple(text: str) -> Step | None:
    """The step, when ``text`` is simple enough for :data:`_SIMPLE_CALL`; else None."""
    out: list[Action] = []
    pos, end = 0, len(text)
    while pos < end:
        m = _SIMPLE_CALL.match(text, pos)
        if m is None:
            return None
        pos = m.end()
        call = m.group(0)
        known = _SIMPLE_CALLS.get(call)
        if known is not None:
            out.append(known)
            continue
        name, number, double_quoted, single_quoted = m.groups()
        entry = _CALLS.get(name)
        if entry is None:
            return None
        cls, kind, _ = entry
        quoted = double_quoted if double_quoted is not None else single_quoted
        if kind == _NUMBER:
            if number is None:
                return None
            value = float(number)
            if not math.isfinite(value):
                return None
            out.append(cls(value))
        elif kind == _STRING:
            if quoted is None:
                return None
            out.append(cls(quoted))
        elif number is None and quoted is None:
            out.append(cls())
        elif (kind in (_OBJECT, _TARGET) and number is not None and number.isdigit() and number.isascii()
              and len(number) <= 18):  # huge ids: the full parser says what is wrong
            out.append(cls(int(number)))
        else:
            return None
        if len(_SIMPLE_CALLS) >= 8192:
            _SIMPLE_CALLS.clear()
        _SIMPLE_CALLS[call] = out[-1]
    return tuple(out) if out else None


#: Text of one call (as matched, separator included) -> its primitive: the same calls recur
#: across steps ("rotate_right(30)"), and primitives are immutable.
_SIMPLE_CALLS: dict[str, Action] = {}


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
    name = _NAMES.get(type(action))
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
    if type(action) not in _NAMES:
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

