"""The action language: parser, printer, clipping, and the Gymnasium action spaces."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from legent_gym.agent.actions import (
    ACTION_TYPES,
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
    clip_action,
    clip_step,
    format_action,
    format_actions,
    parse_actions,
)
from legent_gym.envs.action_spaces import (
    DICT_KEYS,
    SPEECH_CHARSET,
    TEXT_ACTION_CHARSET,
    actions_to_dict,
    continuous_action_space,
    dict_to_actions,
    noop_dict,
    speech_space,
    text_action_space,
)

# ----------------------------------------------------------------------------- parser


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ('speak("Hello.")', Speak("Hello.")),
        ("move_forward(1.2)", MoveForward(1.2)),
        ("rotate_right(-35)", RotateRight(-35.0)),
        ("rotate_down(10)", RotateDown(10.0)),
        ("interact()", Interact()),
        ("interact(7)", Interact(7)),
        ('interact("inner")', Interact("inner")),
        ("grab()", Grab()),
        ("grab(12)", Grab(12)),
        ("put()", Put()),
        ("put(3)", Put(3)),
        ("release()", Put()),  # LEGENT's name, which its own parser could not read
        ("release(4)", Put(4)),
        ("open()", Open()),
        ("open(5)", Open(5)),
        ('open("inner")', Open("inner")),
        ("open(inner)", Open("inner")),  # a bare name is a door id
        ("close(front_door)", Close("front_door")),
        ("close('inner')", Close("inner")),
        ("finish()", Finish()),
    ],
)
def test_every_primitive(text, expected):
    assert parse_actions(text) == (expected,)


def test_several_primitives_in_order():
    step = parse_actions('move_forward(1.8), rotate_right(30), grab(), speak("ok"), finish()')
    assert step == (MoveForward(1.8), RotateRight(30), Grab(), Speak("ok"), Finish())


@pytest.mark.parametrize(
    "text",
    [
        "move_forward(1),rotate_right(2)",
        "  move_forward ( 1 ) ,\n\trotate_right(\t2\t)  ",
        "move_forward(1), rotate_right(2),",  # trailing comma
        "move_forward(1)\u00a0,\u2003rotate_right(2)",  # unicode spaces
        "move_forward(+1.0), rotate_right(2e0)",
        "move_forward(1.), rotate_right(.2e1)",
    ],
)
def test_whitespace_and_number_variants(text):
    assert parse_actions(text) == (MoveForward(1.0), RotateRight(2.0))


@pytest.mark.parametrize(
    ("literal", "value"),
    [("1", 1.0), ("-35", -35.0), ("1.2", 1.2), (".5", 0.5), ("1e-3", 0.001),
     ("-2.5E+2", -250.0), ("0.1", 0.1), ("-0", -0.0)],
)
def test_numbers(literal, value):
    (action,) = parse_actions(f"rotate_down({literal})")
    assert action.degrees == value and isinstance(action.degrees, float)


def test_zero_moves_are_kept():
    # LEGENT's parser dropped these; here they are ordinary primitives.
    assert parse_actions("move_forward(0), rotate_right(0.0), rotate_down(-0)") == (
        MoveForward(0), RotateRight(0), RotateDown(0))


@pytest.mark.parametrize(
    ("literal", "text"),
    [
        (r'"say \"hi\""', 'say "hi"'),
        (r"'It\'s here'", "It's here"),
        ('"It\'s here"', "It's here"),
        ("'say \"hi\"'", 'say "hi"'),
        (r'"a\\b"', "a\\b"),
        (r'"line\nnext\ttab"', "line\nnext\ttab"),
        (r'"caf\u00e9"', "café"),
        (r'"\ud83d\ude00"', "\U0001f600"),  # a surrogate pair is one character
        ('"猫はソファの上 🐈"', "猫はソファの上 🐈"),
        (r'"\/\r\b\f"', "/\r\b\f"),
        ('""', ""),
    ],
)
def test_string_escapes_and_unicode(literal, text):
    assert parse_actions(f"speak({literal})") == (Speak(text),)


def test_large_ids():
    assert parse_actions(f"grab({10**30})") == (Grab(10**30),)
    assert parse_actions("grab(0), put(007)") == (Grab(0), Put(7))


def _error(text: str) -> ActionParseError:
    with pytest.raises(ActionParseError) as info:
        parse_actions(text)
    err = info.value
    assert err.text == text and isinstance(err, ValueError)
    assert f"position {err.position}" in str(err)
    return err


@pytest.mark.parametrize(
    ("text", "position", "message"),
    [
        ("", 0, "empty action at position 0"),
        ("  \n ", 4, "empty action"),
        ("jump()", 0, "unknown action 'jump' at position 0; known: speak, move_forward,"),
        ("moveforward(1)", 0, "did you mean move_forward?"),
        ("move_forward(1), move_forward()", 30, "move_forward() needs a number (metres) at position 30"),
        ('move_forward("far")', 13, "move_forward() needs a number (metres) at position 13, found"),
        ("rotate_right()", 13, "rotate_right() needs a number (degrees)"),
        ('speak("hello', 6, "unterminated string starting at position 6"),
        ("speak('it\\')", 6, "unterminated string"),
        ("move_forward(1.2) x", 18, "expected ',' or end of input at position 18, found 'x'"),
        ("move_forward(1.2) rotate_right(3)", 18, "expected ',' or end of input"),
        ("speak()", 6, "speak() needs a quoted string at position 6"),
        ("speak(hi)", 6, "speak() needs a quoted string"),
        ("finish(1)", 7, "finish() takes no argument"),
        ("grab(1.5)", 5, "grab() needs an integer object id at position 5, found '1.5'"),
        ("grab(1e2)", 5, "needs an integer object id"),
        ("grab(-1)", 5, "grab() needs a non-negative object id"),
        ('grab("cup")', 5, "grab() takes an object id"),
        ("put(table)", 4, "put() takes an object id"),
        ("open(1.5)", 5, "needs an integer object id"),
        ('open("")', 5, "door id must not be empty"),
        ("move_forward(nan)", 13, "non-finite number 'nan'"),
        ("move_forward(inf)", 13, "non-finite number 'inf'"),
        ("rotate_right(-inf)", 13, "non-finite number '-inf'"),
        ("move_forward(1e999)", 13, "non-finite number '1e999'"),
        ("open(Infinity)", 5, "non-finite number"),
        ("move_forward(1, 2)", 14, "takes at most one argument"),
        ("move_forward 1", 13, "expected '(' after move_forward"),
        ("move_forward(1", 14, "expected ')' at position 14, found end of input"),
        (",", 0, "expected an action name at position 0, found ','"),
        ("move_forward(1),,", 16, "expected an action name"),
        ("move_forward(1e)", 14, "malformed exponent"),
        ("move_forward(-)", 13, "malformed number"),
        ("move_forward(2 m)", 15, "expected ')'"),
        ("move_forward(distance=1)", 21, "unexpected character '='"),
        ("speak('\\q')", 7, "unknown escape sequence"),
        ('speak("\\u12")', 7, "4 hex digits"),
        ("grab(" + "9" * 5000 + ")", 5, "object id is too large"),
        ("move_forward(١)", 13, "unexpected character"),  # non-ASCII digits are not numbers
    ],
)
def test_errors_say_what_and_where(text, position, message):
    err = _error(text)
    assert err.position == position
    assert message in str(err)


def test_error_reason_has_no_position_and_errors_pickle():
    err = _error("jump()")
    assert err.reason == "unknown action 'jump'"
    again = pickle.loads(pickle.dumps(err))
    assert (again.text, again.position, again.reason, str(again)) == (
        err.text, err.position, err.reason, str(err))


def test_parse_rejects_non_strings():
    with pytest.raises(TypeError):
        parse_actions(b"finish()")  # type: ignore[arg-type]


# ----------------------------------------------------------------------------- printer


def test_format_is_canonical():
    assert format_actions((MoveForward(1.2), RotateRight(-35))) == "move_forward(1.2), rotate_right(-35)"
    assert format_actions([Speak("It's on the sofa.")]) == 'speak("It\'s on the sofa.")'
    assert format_action(MoveForward(1.0)) == "move_forward(1)"
    assert format_action(MoveForward(0)) == "move_forward(0)"
    assert format_action(RotateDown(1e-7)) == "rotate_down(1e-07)"
    assert format_action(Put(3)) == "put(3)"
    assert format_action(Open("inner")) == 'open("inner")'
    assert format_action(Finish()) == "finish()"
    assert format_action(Speak('a "b"\n')) == r'speak("a \"b\"\n")'


def test_format_rejects_empty_step_and_non_actions():
    with pytest.raises(ValueError, match="empty step"):
        format_actions(())
    with pytest.raises(TypeError):
        format_action("move_forward(1)")  # type: ignore[arg-type]


def test_round_trip_edge_cases():
    steps = [
        (Speak("\ud800 lone surrogate"),),
        (Speak("\x00\x1f\x7f\u2028"),),
        (Open("12"), Open(12), Close("a b"), Interact("\\")),
        (MoveForward(5e-324), RotateRight(-1.7976931348623157e308), RotateDown(-0.0)),
    ]
    for step in steps:
        assert parse_actions(format_actions(step)) == step


def test_dataclasses_validate_and_normalise():
    assert MoveForward(np.float32(0.5)).distance == 0.5
    assert type(MoveForward(np.float32(0.5)).distance) is float
    assert type(Grab(np.int64(3)).target) is int
    for bad in (lambda: MoveForward(math.nan), lambda: RotateRight(math.inf),
                lambda: Grab(-1), lambda: Open("")):
        with pytest.raises(ValueError):
            bad()
    for bad in (lambda: Grab("door"), lambda: Put(1.5), lambda: MoveForward("1"),
                lambda: Speak(3), lambda: Grab(True)):
        with pytest.raises(TypeError):
            bad()


# ----------------------------------------------------------------------------- properties

_finite = st.floats(allow_nan=False, allow_infinity=False)
_ids = st.integers(min_value=0, max_value=10**40)
_doors = st.text(min_size=1, max_size=12)
_any_target = st.none() | _ids | _doors
_object_target = st.none() | _ids
_actions = st.one_of(
    st.builds(Speak, st.text(max_size=30)),
    st.builds(MoveForward, _finite),
    st.builds(RotateRight, _finite),
    st.builds(RotateDown, _finite),
    st.builds(Interact, _any_target),
    st.builds(Grab, _object_target),
    st.builds(Put, _object_target),
    st.builds(Open, _any_target),
    st.builds(Close, _any_target),
    st.just(Finish()),
)
_steps = st.lists(_actions, min_size=1, max_size=4).map(tuple)

# Grammar-shaped pieces, so that many generated strings are valid or nearly valid. Each
# piece is coded as one CJK character and drawn with st.text(), which hypothesis generates
# several times faster than a list of sampled strings (10,000 examples must fit in a few
# seconds) and still shrinks to the fewest pieces.
_PIECES = [
    "speak", "move_forward", "rotate_right", "rotate_down", "interact", "grab", "put",
    "release", "open", "close", "finish", "inner", "nan", "inf", "-inf", "jump", "Speak",
    "(", ")", ",", ", ", " ", "\t", "\n", '"', "'", "\\", "\\u", "\\u00e9", "\\ud83d",
    '\\"', "-", "+", ".", "e", "E", "1e999", "0", "12", "1.5", ".5", "1e-3", "-35", "=",
    "()", "(1)", '("hi")', "é", "猫", "\u00a0",
    # Whole call openers and calls make near-valid steps common.
    "move_forward(", "rotate_right(", "rotate_down(", "speak(", "grab(", "open(", "close(",
    "interact(", "put(", "finish()", "release()", "), ",
]
_CODES = "".join(chr(0x4E00 + i) for i in range(len(_PIECES)))
_DECODE = dict(zip(_CODES, _PIECES))
_grammar_shaped = st.text(alphabet=_CODES, max_size=14).map(
    lambda s: "".join(_DECODE[c] for c in s))

# Valid steps covering every primitive, to be damaged by one splice below.
_VALID = [
    'move_forward(1.8), rotate_right(30)',
    'speak("It\'s on the sofa."), finish()',
    "rotate_down(-1e-3), grab(12), put(), release(3),",
    "interact(), open(inner), close('front')",
    'speak("caf\\u00e9 \\"x\\" \\\\"), move_forward(0)',
]


def _splice(parts: tuple[str, int, int, str]) -> str:
    """``text`` with ``n`` characters at ``at`` replaced by ``insert``."""
    text, at, n, insert = parts
    at %= len(text) + 1
    return text[:at] + insert + text[at + n:]


_damaged = st.tuples(
    st.sampled_from(_VALID), st.integers(0, 80), st.integers(0, 3),
    st.text(max_size=2) | _grammar_shaped,
).map(_splice)


@settings(max_examples=10_000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.text(), _grammar_shaped, _damaged))
def test_parser_returns_actions_or_raises_parse_error(text):
    try:
        step = parse_actions(text)
    except ActionParseError as err:
        assert err.text == text
        assert 0 <= err.position <= len(text)
        assert f"position {err.position}" in str(err)
        return
    assert isinstance(step, tuple) and step
    assert all(isinstance(a, ACTION_TYPES) for a in step)
    assert parse_actions(format_actions(step)) == step


@settings(max_examples=800, deadline=None)
@given(_steps)
def test_format_then_parse_is_identity(step):
    assert parse_actions(format_actions(step)) == step


# ----------------------------------------------------------------------------- clipping


def test_clip_action_notes():
    limits = ActionLimits()
    assert clip_action(MoveForward(3.5), limits) == (
        MoveForward(2.0), "move_forward(3.5) clipped to 2.0 m")
    clipped, note = clip_action(MoveForward(-1), limits)
    assert clipped == MoveForward(0) and "no walking backwards" in note
    assert clip_action(MoveForward(1.5), limits) == (MoveForward(1.5), None)
    assert clip_action(RotateRight(-120), limits) == (
        RotateRight(-90), "rotate_right(-120) clipped to -90.0 degrees")
    assert clip_action(RotateDown(100), limits)[0] == RotateDown(90)
    clipped, note = clip_action(Speak("x" * 600), limits)
    assert clipped == Speak("x" * 500) and note == "speech of 600 characters truncated to 500"
    assert clip_action(Grab(3), limits) == (Grab(3), None)
    assert clip_action(Finish(), limits) == (Finish(), None)


def test_clip_keeps_pitch_in_range():
    limits = ActionLimits()
    clipped, note = clip_action(RotateDown(30), limits, pitch=50.0)
    assert clipped == RotateDown(10) and "pitch" in note
    assert clip_action(RotateDown(-30), limits, pitch=-50.0)[0] == RotateDown(-10)
    # A head already past the limit may tilt back, and is not pushed further.
    assert clip_action(RotateDown(-5), limits, pitch=70.0) == (RotateDown(-5), None)
    assert clip_action(RotateDown(5), limits, pitch=70.0)[0] == RotateDown(0)
    # Float noise must not produce a note when nothing is clipped.
    assert clip_action(RotateDown(0.2), limits, pitch=0.1) == (RotateDown(0.2), None)
    step, notes = clip_step([RotateDown(40), RotateDown(40), MoveForward(9)], limits, pitch=0.0)
    assert step == (RotateDown(40), RotateDown(20), MoveForward(2)) and len(notes) == 2


def test_limits_validate():
    with pytest.raises(ValueError):
        ActionLimits(pitch_range=(10.0, -10.0))
    with pytest.raises(ValueError):
        ActionLimits(max_move=-1)


# ----------------------------------------------------------------------------- spaces


def _same_dict(a: dict, b: dict) -> bool:
    """Equal keys in the same order and exactly equal values (float32 compared exactly)."""
    if list(a) != list(b):
        return False
    for key in a:
        x, y = a[key], b[key]
        if isinstance(x, str) or isinstance(y, str):
            if x != y:
                return False
        elif not np.array_equal(np.asarray(x), np.asarray(y)):
            return False
    return all(np.asarray(b[k]).dtype == np.float32 for k in DICT_KEYS[:3])


def test_dict_space_layout():
    space = continuous_action_space(ActionLimits(max_move=1.5, max_speech_chars=40))
    assert list(space.spaces) == list(DICT_KEYS)
    assert float(space["move_forward"].high) == 1.5 and float(space["move_forward"].low) == 0
    assert space["move_forward"].shape == () and space["move_forward"].dtype == np.float32
    assert float(space["rotate_right"].low) == -90 and float(space["rotate_down"].high) == 90
    assert space["interact"].n == 6 and space["finish"].n == 2
    assert space["speak"].max_length == 40 and space["speak"].min_length == 0
    assert space.contains(noop_dict())
    assert dict_to_actions(noop_dict()) == ()


def test_space_contains():
    space = continuous_action_space()
    good = noop_dict() | {"move_forward": np.array(1.5, np.float32), "interact": np.int64(2),
                          "speak": "It's on the sofa, café!"}
    assert space.contains(good)
    assert not space.contains(good | {"move_forward": np.array(2.5, np.float32)})
    assert not space.contains(good | {"interact": np.int64(6)})
    assert not space.contains(good | {"speak": "tab\there"})


def test_speech_and_text_spaces():
    speech = speech_space()
    assert speech.contains("It's on the sofa. Where? (Kitchen) 50% 3/4 cost $5 #1 @home!")
    assert speech.contains("Ça va? Über naïve fiancée, señor. “Yes” — it’s…")
    assert speech.contains("")
    assert not speech.contains("x" * 501)
    assert set(SPEECH_CHARSET) <= set(TEXT_ACTION_CHARSET)
    text = text_action_space()
    code = 'move_forward(1.2), rotate_right(-35), speak("It\'s \\"here\\"\\n"), grab(1e-3)'
    assert text.contains(code) and text.max_length == 1000
    assert not text.contains("x" * 1001)


def test_sampled_dicts_round_trip_through_actions_and_text():
    space = continuous_action_space()
    space.seed(1234)
    limits = ActionLimits()
    for _ in range(500):
        d = space.sample()
        step = dict_to_actions(d)
        assert _same_dict(actions_to_dict(step, limits=limits, strict=True), d)
        if step:  # the no-op dict's empty step has no text form
            again = parse_actions(format_actions(step))
            assert again == step
            assert _same_dict(actions_to_dict(again, limits=limits, strict=True), d)


def test_representable_steps_round_trip():
    steps = [
        (MoveForward(1.5), RotateRight(-30), RotateDown(10), Grab(), Speak("Hi!"), Finish()),
        (RotateRight(45.25), Close()),
        (Interact(),),
        (Speak("On the sofa."),),
        (Finish(),),
        (),
    ]
    for step in steps:
        d = actions_to_dict(step, strict=True)
        assert continuous_action_space().contains(d)
        assert dict_to_actions(d) == step


def test_actions_to_dict_rounds_to_float32_unless_strict():
    d = actions_to_dict((MoveForward(1.2),))
    assert d["move_forward"] == np.float32(1.2)
    with pytest.raises(ValueError, match="not exact in float32"):
        actions_to_dict((MoveForward(1.2),), strict=True)


@pytest.mark.parametrize(
    ("step", "message"),
    [
        ((RotateRight(30), MoveForward(1)), "executes in the order move_forward, rotate_right"),
        ((Speak("a"), Grab()), "executes in the order"),
        ((Grab(), Put()), "'interact' slot is already used by grab()"),
        ((MoveForward(1), MoveForward(1)), "already used"),
        ((Grab(12),), "no object ids"),
        ((Put(3),), "no object ids"),
        ((Open("inner"),), "no door ids"),
        ((MoveForward(0),), "0 means 'absent'"),
        ((RotateDown(0),), "0 means 'absent'"),
        ((Speak(""),), "'absent'"),
        ((MoveForward(-1),), "no walking backwards"),
        ((Speak("tab\there"),), "outside SPEECH_CHARSET"),
        ((RotateRight(1e-60),), "float32"),
        ((MoveForward(3.0),), "outside [0.0, 2.0]"),
        ((Speak("x" * 501),), "longer than 500"),
    ],
)
def test_actions_to_dict_errors(step, message):
    with pytest.raises(ValueError) as info:
        actions_to_dict(step, limits=ActionLimits())
    assert message in str(info.value)


def test_dict_to_actions_inputs():
    assert dict_to_actions({"move_forward": 1.0, "interact": 4}) == (MoveForward(1.0), Open())
    assert dict_to_actions({"rotate_down": np.array([-5.0]), "finish": np.int64(1)}) == (
        RotateDown(-5), Finish())
    assert dict_to_actions({"move_forward": np.float32(-0.0)}) == ()
    with pytest.raises(ValueError, match="unknown action keys"):
        dict_to_actions({"jump": 1})
    with pytest.raises(ValueError, match="interact"):
        dict_to_actions({"interact": 6})
    with pytest.raises(ValueError, match="finish"):
        dict_to_actions({"finish": 0.5})
    with pytest.raises(ValueError):
        dict_to_actions({"move_forward": np.array(np.nan)})
