"""The paper's intermediate code: what an expert (or an LLM) writes between instruction and controls.

A program is a sequence of calls, separated by whitespace, newlines or commas::

    goto(12) target(12) interact() goto_user()
    find(7)
    speak("It's on the sofa.")

=====================  ==================================================================
``goto_user()``        walk to the user (stop short of them, within talking distance)
``goto(a)``            walk to where object ``a`` is within reach, and face it
``find(a)``            walk until ``a`` is within 3 m and in sight, then look at it
``target(a)``          aim the camera (yaw and pitch) so that ``interact()`` hits ``a``
``interact()``         LEGENT's generic grab / put / open / close at the image centre
``grab()`` ``put()``   the explicit forms (also ``open()``, ``close()``; each may take an
                       object id, and ``open``/``close`` a door id in quotes)
``speak("...")``       say something
``finish()``           declare the task done
=====================  ==================================================================

Object ids are the scene's integer ids. The parser reuses the action language's tokenizer
(never ``eval``); :func:`check_program` checks ids against a scene. Every error names the
call and the character position, so that an LLM can be told what to fix.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

# The tokenizer and quoting of the action language: one lexical grammar for both languages.
from legent_gym.agent.actions import ActionParseError, Tokenizer, format_number, quote_string

__all__ = ["INSTRUCTIONS", "Instruction", "Program", "ProgramError", "check_program", "format_program",
           "parse_program"]

#: Each instruction's argument: ``None`` (no argument), ``"object"`` (a required object id),
#: ``"target?"`` (optional object id or door id), ``"text"`` (a required string).
INSTRUCTIONS: dict[str, str | None] = {
    "goto_user": None,
    "goto": "object",
    "find": "object",
    "target": "object",
    "interact": "target?",
    "grab": "target?",
    "put": "target?",
    "open": "target?",
    "close": "target?",
    "speak": "text",
    "finish": None,
}
#: Instructions that act once (one primitive); the others are carried out by a planner
#: over as many actions as they need.
ONE_SHOT = frozenset({"interact", "grab", "put", "open", "close", "speak", "finish"})


class ProgramError(ValueError):
    """Intermediate code that cannot run: bad syntax, an unknown function, a wrong argument or
    an id that is not in the scene. ``position`` is the character index (-1 when unknown)."""

    def __init__(self, text: str, position: int, reason: str):
        self.text, self.position, self.reason = text, position, reason
        where = f" at position {position}" if position >= 0 else ""
        super().__init__(f"{reason}{where}")

    def __reduce__(self):
        return (type(self), (self.text, self.position, self.reason))


@dataclass(frozen=True)
class Instruction:
    """One call: ``name`` and its argument (``None``, an object id, a door id or a text)."""

    name: str
    arg: int | str | None = None
    position: int = -1  # where it starts in the source, for error messages

    def __post_init__(self) -> None:
        if self.name not in INSTRUCTIONS:
            raise ValueError(f"unknown instruction {self.name!r}; known: {', '.join(INSTRUCTIONS)}")

    def __str__(self) -> str:
        if self.arg is None:
            return f"{self.name}()"
        if isinstance(self.arg, str):
            return f"{self.name}({quote_string(self.arg)})"
        return f"{self.name}({format_number(self.arg) if isinstance(self.arg, float) else self.arg})"

    def object_arg(self) -> int:
        """The argument as an object id (what ``goto``, ``find`` and ``target`` take);
        ``TypeError`` if it is none or a text."""
        if self.arg is None or isinstance(self.arg, str):
            raise TypeError(f"{self}: the argument must be an object id, got {self.arg!r}")
        return self.arg

    def text_arg(self) -> str:
        """The argument as a text (what ``speak`` takes); ``TypeError`` if it is not one."""
        if not isinstance(self.arg, str):
            raise TypeError(f"{self}: the argument must be a text, got {self.arg!r}")
        return self.arg


Program = tuple[Instruction, ...]


def format_program(program: Iterable[Instruction]) -> str:
    """The canonical text of a program: calls joined by spaces."""
    return " ".join(str(i) for i in program)


def parse_program(text: str) -> Program:
    """Parse intermediate code into a :data:`Program`.

    >>> parse_program('goto(3) target(3) interact()')[0]
    Instruction(name='goto', arg=3, position=0)

    Raises:
        ProgramError: naming what is wrong and where.
    """
    if not isinstance(text, str):
        raise ProgramError(repr(text), -1, f"intermediate code must be a string, got {type(text).__name__}")
    try:
        tokens = Tokenizer(text).tokens()
    except ActionParseError as err:
        raise ProgramError(text, err.position, err.reason) from None
    out: list[Instruction] = []
    i = 0

    def expect(kind: str, what: str):
        nonlocal i
        tok = tokens[i]
        if tok.kind != kind:
            raise ProgramError(text, tok.pos, f"expected {what}, found {tok.describe()}")
        i += 1
        return tok

    while tokens[i].kind != "END":
        if tokens[i].kind == "COMMA":
            i += 1
            continue
        name = expect("NAME", "a function name such as goto(...)")
        if name.value not in INSTRUCTIONS:
            raise ProgramError(text, name.pos, f"unknown function {name.value!r}; known: "
                                               f"{', '.join(INSTRUCTIONS)}")
        expect("LPAREN", f"'(' after {name.value}")
        kind = INSTRUCTIONS[name.value]
        arg: int | str | None = None
        tok = tokens[i]
        if tok.kind != "RPAREN":
            if kind is None:
                raise ProgramError(text, tok.pos, f"{name.value}() takes no argument, found {tok.describe()}")
            if tok.kind == "NUMBER":
                if not tok.value.lstrip("+").isdigit():
                    raise ProgramError(text, tok.pos, f"{name.value}() needs an integer object id, found {tok.raw!r}")
                if kind == "text":
                    raise ProgramError(text, tok.pos, f"{name.value}() needs a quoted text, found {tok.raw!r}")
                arg = int(tok.value)
            elif tok.kind == "STRING":
                if kind == "object":
                    raise ProgramError(text, tok.pos, f"{name.value}() needs an integer object id, found {tok.raw!r}")
                arg = tok.value
            else:
                raise ProgramError(text, tok.pos, f"bad argument to {name.value}(): {tok.describe()}")
            i += 1
        elif kind in ("object", "text"):
            what = "an object id" if kind == "object" else "a quoted text"
            raise ProgramError(text, tok.pos, f"{name.value}() needs {what}")
        expect("RPAREN", f"')' to close {name.value}(")
        out.append(Instruction(name.value, arg, name.pos))
    if not out:
        raise ProgramError(text, 0, "empty program")
    return tuple(out)


def check_program(program: Program, object_ids: Iterable[int], door_ids: Iterable[str] = ()) -> None:
    """Raise :class:`ProgramError` if an instruction names an object or door the scene lacks."""
    objects, doors = set(object_ids), set(door_ids)
    source = format_program(program)
    for ins in program:
        if isinstance(ins.arg, int) and ins.arg not in objects:
            raise ProgramError(source, ins.position, f"{ins.name}({ins.arg}): no object with id {ins.arg} in the scene")
        if isinstance(ins.arg, str) and ins.name in ("open", "close", "interact") and ins.arg not in doors:
            raise ProgramError(source, ins.position, f"{ins.name}({ins.arg!r}): no door with id {ins.arg!r}")
        if isinstance(ins.arg, str) and ins.name in ("grab", "put"):
            raise ProgramError(source, ins.position, f"{ins.name}() takes an object id, not {ins.arg!r}")
