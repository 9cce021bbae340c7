"""Action text -> a step: :func:`parse_actions`, its :class:`Tokenizer` and
:class:`ActionParseError`. A hand-written tokenizer and recursive-descent parser (never
``eval``): every error says what is wrong and at which character."""

from __future__ import annotations

import difflib
import functools
import math
import re
from dataclasses import dataclass

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
    Step,
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

