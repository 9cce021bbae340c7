"""The intermediate code: parsing, printing, errors, id checks, and running code on an env."""

from __future__ import annotations

import contextlib

import gymnasium as gym
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import legent_gym  # noqa: F401
from legent_gym.experts import (
    Instruction,
    ProgramError,
    ProgramExecutor,
    format_program,
    parse_program,
)
from legent_gym.experts.program import check_program
from legent_gym.tasks.feasibility import stand_leg


def test_parses_the_papers_table():
    program = parse_program('goto(3) target(3) interact() goto_user()')
    assert [i.name for i in program] == ["goto", "target", "interact", "goto_user"]
    assert program[0].arg == 3 and program[2].arg is None
    spoken = parse_program('find(7)\nspeak("It\'s on the sofa.")')
    assert spoken[1] == Instruction("speak", "It's on the sofa.", spoken[1].position)


def test_separators_and_explicit_forms():
    program = parse_program("goto(1), grab(1) , put(2)\topen('inner') close() finish()")
    assert [str(i) for i in program] == ["goto(1)", "grab(1)", "put(2)", 'open("inner")', "close()", "finish()"]


@pytest.mark.parametrize("text, reason", [
    ("", "empty program"),
    ("jump()", "unknown function 'jump'"),
    ("goto()", "goto() needs an object id"),
    ("goto(1.5)", "needs an integer object id"),
    ('goto("sofa")', "needs an integer object id"),
    ("goto_user(3)", "takes no argument"),
    ("speak(3)", "needs a quoted text"),
    ("goto(3", "expected ')'"),
    ("goto 3", "expected '(' after goto"),
    ('speak("open', "unterminated string"),
    ("goto(3); finish()", "unexpected character ';'"),
    ("__import__('os')", "unknown function '__import__'"),
])
def test_syntax_errors_name_the_problem(text, reason):
    with pytest.raises(ProgramError) as err:
        parse_program(text)
    assert reason in str(err.value)


def test_not_a_string():
    with pytest.raises(ProgramError, match="must be a string"):
        parse_program(None)  # type: ignore[arg-type]


def test_ids_are_checked_against_the_scene():
    check_program(parse_program("goto(1) open('inner')"), [1, 2], ["inner"])
    with pytest.raises(ProgramError, match="no object with id 9"):
        check_program(parse_program("goto(1) goto(9)"), [1, 2])
    with pytest.raises(ProgramError, match="no door with id 'front'"):
        check_program(parse_program("open('front')"), [1], ["inner"])


_instruction = st.one_of(
    st.sampled_from(["goto_user", "interact", "grab", "put", "open", "close", "finish"]).map(Instruction),
    st.tuples(st.sampled_from(["goto", "find", "target", "grab", "put"]), st.integers(0, 10**6))
      .map(lambda t: Instruction(*t)),
    st.text(max_size=30).map(lambda s: Instruction("speak", s)),
)


@settings(max_examples=300, deadline=None)
@given(st.lists(_instruction, min_size=1, max_size=6))
def test_print_parse_round_trip(program):
    parsed = parse_program(format_program(program))
    assert [(i.name, i.arg) for i in parsed] == [(i.name, i.arg) for i in program]


@settings(max_examples=500, deadline=None)
@given(st.text(max_size=60))
def test_parser_never_fails_otherwise(text):
    with contextlib.suppress(ProgramError):
        parse_program(text)


def _run(env, executor, limit=25):
    for _ in range(limit):
        _, _, terminated, truncated, info = env.step(executor.action())
        if terminated or truncated:
            return info
    return info


def test_executor_runs_code_written_by_anyone():
    env = gym.make("Legent/ComeHere-OneRoom-v0", width=32, height=32)
    env.reset(seed=0)
    info = _run(env, ProgramExecutor(env, "goto_user()"))
    assert info["success"]
    env.close()


def test_executor_visits_every_goal_of_a_multi_goto_plan():
    # LEGENT's planner went to the first target only; ours walks to each in turn.
    env = gym.make("Legent/GoTo-TwoRoom-v0", width=32, height=32, max_episode_steps=60)
    env.reset(seed=0)
    ctx = env.unwrapped.episode.ctx
    # objects someone could walk up to (one on a bed in a corner may have no standing point)
    reachable = [o.id for o in ctx.scene.objects
                 if o.kind == "interactable" and stand_leg(ctx, o.id, "aim") is not None]
    a, b = reachable[0], reachable[-1]
    executor = ProgramExecutor(env, f"goto({a}) goto({b})")
    visited = set()
    for _ in range(60):
        before = executor.pc
        env.step(executor.action())
        if executor.pc > before or executor.done:
            visited.add(executor.program[before].arg)
        if executor.done:
            break
    assert executor.done and visited == {a, b}
    assert ctx.reach_distance(ctx.agent.position, b) <= ctx.agent.reach
    env.close()


def test_executor_rejects_unknown_ids():
    env = gym.make("Legent/ComeHere-OneRoom-v0", width=32, height=32)
    env.reset(seed=0)
    with pytest.raises(ProgramError, match="no object with id 99999"):
        ProgramExecutor(env, "goto(99999)")
    env.close()
