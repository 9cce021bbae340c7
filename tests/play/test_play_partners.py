"""``legent-gym play`` as the user with each kind of partner driving the agent (``random``,
``module:function``, ``llm`` against a real OpenAI-compatible server on the loopback interface), and
two players at once (two browser tabs on one server): the real command in a child process,
spoken to over its WebSocket."""

from __future__ import annotations

import json
import math
import time

import pytest
import websockets.sync.client as ws_client

from tests.chat_server import ReplayServer
from tests.play.test_play import SMALL, play_server, receive_json, ws_url
from tests.play_partner import TURN

INSTRUCTION = "Please come here."


def turn(before: list[float], after: list[float]) -> float:
    """The agent's turn to the right between two poses (x, y, yaw in degrees anticlockwise,
    pitch), in [-180, 180): what ``rotate_right`` was given."""
    return (before[2] - after[2] + 180) % 360 - 180


def agent_states(ws, steps: int, timeout: float = 120.0) -> list[dict]:
    """The states after each of the partner's first ``steps`` steps (the person waits; the
    agent acts every ``--tick``)."""
    by_step: dict[int, dict] = {}
    deadline = time.monotonic() + timeout
    while len(by_step) < steps + 1:
        state = receive_json(ws, "state", timeout=max(0.1, deadline - time.monotonic()))
        assert not state["partner_error"], state["partner_error"]
        by_step[state["actions_used"]] = state
    return [by_step[k] for k in sorted(by_step)][: steps + 1]


def instruct(ws) -> dict:
    """Say the instruction (the person's first words: the agent's instruction)."""
    assert receive_json(ws, "hello", timeout=120)["role"] == "user"
    assert receive_json(ws, "state")["actions_used"] == 0
    ws.send(json.dumps({"type": "say", "text": INSTRUCTION}))
    state = receive_json(ws, "state")
    assert state["agent_instructed"] and state["actions_used"] == 1
    return state


def test_random_partner_makes_one_random_move_turn_or_tilt_a_step():
    with play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL, "--partner", "random", "--tick", "0.2",
                     "--seed", "2") as url, \
            ws_client.connect(ws_url(url), open_timeout=60) as ws:
        said = instruct(ws)
        states = agent_states(ws, 8)
    assert said["partner"] == "random"
    poses = [said["agent_pose"]] + [s["agent_pose"] for s in states[1:]]
    turns = [turn(a, b) for a, b in zip(poses, poses[1:])]
    moves = [math.dist(a[:2], b[:2]) for a, b in zip(poses, poses[1:])]
    for t, m in zip(turns, moves):  # a step is a move (<= 1.5 m), a turn (<= 90 degrees) or a tilt
        assert (abs(t) < 1e-6 and m <= 1.5 + 1e-6) or (0 < abs(t) <= 90 + 1e-6 and m < 1e-6), (t, m)
    assert any(abs(t) > 1e-6 for t in turns) and any(m > 1e-6 for m in moves)  # both kinds, from seed 2
    assert len({round(abs(t), 1) for t in turns if abs(t) > 1e-6}) > 1  # turns of different sizes: random


def test_module_function_partner_is_reset_with_the_instruction_and_drives_the_agent():
    with play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL, "--partner", "tests.play_partner:announcer",
                     "--tick", "0.2") as url, ws_client.connect(ws_url(url), open_timeout=60) as ws:
        said = instruct(ws)
        states = agent_states(ws, 4)
    assert said["partner"] == "tests.play_partner:announcer"
    # its first action: what it was reset with, said aloud
    assert {"who": "agent", "text": f"heard: {INSTRUCTION}"} in states[-1]["transcript"]
    # then a fixed turn a step, standing still
    poses = [s["agent_pose"] for s in states[1:]]
    assert [round(turn(a, b), 3) for a, b in zip(poses, poses[1:])] == [TURN] * (len(poses) - 1)
    assert all(math.dist(a[:2], b[:2]) < 1e-6 for a, b in zip(poses, poses[1:]))


def test_llm_partner_asks_the_endpoint_and_plays_its_reply(monkeypatch):
    monkeypatch.setenv("OPENAI_API_KEY", "test-key")
    script = [("reply", 'speak("On my way.")')]
    with ReplayServer(script, default=("reply", "rotate_right(30)")) as llm, \
            play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL, "--partner", "llm", "--llm-url", llm.url,
                        "--llm-model", "my-model", "--tick", "0.2") as url, \
            ws_client.connect(ws_url(url), open_timeout=60) as ws:
        instruct(ws)
        states = agent_states(ws, 4)
        requests = list(llm.requests)
    assert {"who": "agent", "text": "On my way."} in states[-1]["transcript"]
    poses = [s["agent_pose"] for s in states[1:]]
    assert [round(turn(a, b), 3) for a, b in zip(poses, poses[1:])] == [30.0] * (len(poses) - 1)
    first = requests[0]
    assert first["path"] == "/v1/chat/completions" and first["headers"]["authorization"] == "Bearer test-key"
    assert first["body"]["model"] == "my-model"
    assert f"Instruction: {INSTRUCTION}" in first["body"]["messages"][-1]["content"]
    # each request shows the model its earlier replies
    assert 'speak("On my way.")' in requests[1]["body"]["messages"][-1]["content"]


def test_two_sessions_play_at_once_and_a_third_is_told_the_server_is_busy():
    with play_server("Legent/ComeHere-OneRoom-v0", "--size", SMALL, "--sessions", "2") as url:
        with ws_client.connect(ws_url(url), open_timeout=60) as a, \
                ws_client.connect(ws_url(url), open_timeout=60) as b:
            for ws in (a, b):
                assert receive_json(ws, "hello", timeout=120)["role"] == "user"
                assert receive_json(ws, "state")["actions_used"] == 0
            a.send(json.dumps({"type": "key", "key": "left"}))
            a_state = receive_json(a, "state")
            b.send(json.dumps({"type": "key", "key": "forward"}))
            b.send(json.dumps({"type": "key", "key": "forward"}))
            b_states = [receive_json(b, "state"), receive_json(b, "state")]
            assert a_state["actions_used"] == 1 and [s["actions_used"] for s in b_states] == [1, 2]  # separate envs
            a.send(json.dumps({"type": "key", "key": "right"}))
            assert receive_json(a, "state")["actions_used"] == 2
            with ws_client.connect(ws_url(url), open_timeout=60) as c:
                busy = receive_json(c, "error", timeout=30)
                assert busy.get("fatal") and "2 session(s)" in busy["message"]
        # both places are free again
        with ws_client.connect(ws_url(url), open_timeout=60) as a, \
                ws_client.connect(ws_url(url), open_timeout=60) as b:
            for ws in (a, b):
                assert receive_json(ws, "hello", timeout=120)["role"] == "user"


@pytest.mark.parametrize("sessions", ["0", "-1"])
def test_sessions_below_one_are_refused(capsys, sessions):
    from legent_gym.cli import main

    assert main(["play", "Legent/ComeHere-OneRoom-v0", "--sessions", sessions]) == 2
    assert "--sessions must be >= 1" in capsys.readouterr().err
