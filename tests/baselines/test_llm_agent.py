"""The LLM agent against a real HTTP server on 127.0.0.1 that answers like the chat completions
API: good replies, malformed ones, errors, rate limits and slow replies."""

from __future__ import annotations

import base64
import io
import json
import socket
import time

import gymnasium as gym
import numpy as np
import pytest
from PIL import Image

from baselines.evaluate import run_episodes
from baselines.llm_agent import (
    NOOP_ACTION,
    EndpointError,
    LLMAgent,
    extract_action,
    main,
)
from legent_gym.agent.actions import ActionParseError
from tests.chat_server import HOLD_SECONDS, ReplayServer

ENV_ID = "Legent/ComeHere-OneRoom-v0"


def FakeChatServer(script=(), default=("reply", "rotate_right(45)")):  # noqa: N802 (used as a class)
    """The shared replay server (tests/chat_server.py) answering ``default`` once ``script``
    is used up."""
    return ReplayServer(script, default)


def _agent(server, **kwargs):
    options = {"model": "test-vlm", "api_key": "test-key", "timeout": 5.0, "max_retries": 3, "backoff": 0.0,
               "history": 3}
    return LLMAgent(base_url=server.url, **{**options, **kwargs})


def _images(request) -> list[np.ndarray]:
    out = []
    for part in request["body"]["messages"][1]["content"]:
        if part["type"] == "image_url":
            prefix, data = part["image_url"]["url"].split(",", 1)
            assert prefix == "data:image/png;base64"
            out.append(np.asarray(Image.open(io.BytesIO(base64.b64decode(data)))))
    return out


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# -- good replies, real env steps ---------------------------------------------------------------


def test_agent_sends_interleaved_history_and_steps_the_env():
    replies = ["move_forward(1), rotate_right(30)", "Action: `rotate_right(-45)`",
               "```python\nmove_forward(0.5)\n```", "I will turn left.\nrotate_right(-90)"]
    env = gym.make(ENV_ID, width=32, height=32)
    with FakeChatServer([("reply", r) for r in replies]) as server:
        agent = _agent(server)
        obs, _ = env.reset(seed=0)
        agent.reset(obs["instruction"])
        frames, actions = [obs["rgb"]], []
        for _ in replies:
            action = agent.act(obs)
            obs, _, terminated, truncated, info = env.step(action)
            assert info["action_error"] == "" and not truncated
            frames.append(obs["rgb"])
            actions.append(action)
            if terminated:
                break
    assert actions[:4] == ["move_forward(1), rotate_right(30)", "rotate_right(-45)", "move_forward(0.5)",
                           "rotate_right(-90)"][:len(actions)]
    assert (frames[1] != frames[0]).any()  # the agent moved and turned: its view changed
    first, last = server.requests[0], server.requests[len(actions) - 1]
    assert first["path"] == "/v1/chat/completions"
    assert first["headers"]["authorization"] == "Bearer test-key"
    assert first["body"]["model"] == "test-vlm"
    system = first["body"]["messages"][0]["content"]
    assert obs["instruction"] in system and "move_forward(metres)" in system
    # The images are the env's frames, losslessly; the window keeps the last 3, oldest first.
    assert len(_images(first)) == 1 and (_images(first)[0] == frames[0]).all()
    n = len(actions)
    window = _images(last)
    assert len(window) == min(n, 3)
    assert all((a == b).all() for a, b in zip(window, frames[max(0, n - 3):n]))
    texts = [p["text"] for p in last["body"]["messages"][1]["content"] if p["type"] == "text"]
    assert texts[-1] == "Action:" and texts[0] == "Observation:"
    if n >= 2:
        assert f"Action: {actions[n - 2]}\n" in texts
    assert all(s.fallback is None and s.requests == 1 for s in agent.steps)


def test_run_episodes_with_the_agent_is_deterministic():
    with FakeChatServer(default=("reply", "rotate_right(60), move_forward(1.2)")) as server:
        results = [run_episodes(_agent(server), ENV_ID, 2, seed=3, env_kwargs={"width": 32, "height": 32})
                   for _ in range(2)]
    assert results[0] == results[1]
    assert all(1 <= r.steps <= 25 for r in results[0])


# -- replies that are not actions --------------------------------------------------------------


def test_unparsable_reply_gets_the_parse_error_fed_back():
    script = [("reply", "I should walk towards the user."), ("reply", "jump()"), ("reply", "move_forward(1.5)")]
    with FakeChatServer(script) as server:
        agent = _agent(server, parse_retries=2)
        agent.reset("Come here.")
        action = agent.act({"rgb": np.zeros((32, 32, 3), np.uint8)})
    assert action == "move_forward(1.5)"
    assert agent.steps[0].replies == ["I should walk towards the user.", "jump()", "move_forward(1.5)"]
    third = server.requests[2]["body"]["messages"]
    assert [m["role"] for m in third] == ["system", "user", "assistant", "user", "assistant", "user"]
    assert third[2]["content"] == "I should walk towards the user."
    assert "not valid action code" in third[3]["content"]
    assert "unknown action 'jump'" in third[5]["content"]


def test_persistently_unparsable_replies_fall_back_to_a_noop_with_the_reason():
    with FakeChatServer(default=("reply", "Sorry, I cannot see the user.")) as server:
        agent = _agent(server, parse_retries=1)
        env = gym.make(ENV_ID, width=32, height=32)
        obs, info0 = env.reset(seed=1)
        agent.reset(obs["instruction"])
        action = agent.act(obs)
        _, _, _, _, info = env.step(action)
    assert action == NOOP_ACTION
    assert len(server.requests) == 2
    assert "no valid action code in 2 replies" in agent.steps[0].fallback
    # The fallback is a real no-op: valid code that leaves the agent where it was.
    assert info["action_error"] == "" and info["agent_pose"] == info0["agent_pose"]


def test_empty_content_counts_as_an_unparsable_reply():
    with FakeChatServer([("reply", ""), ("reply", "finish()")]) as server:
        agent = _agent(server)
        agent.reset("Come here.")
        assert agent.act({"rgb": np.zeros((8, 8, 3), np.uint8)}) == "finish()"
    assert "empty action" in server.requests[1]["body"]["messages"][-1]["content"]


@pytest.mark.parametrize("reply, expected", [
    ("move_forward(1.50)", "move_forward(1.5)"),
    ("  action: rotate_right(-30) ", "rotate_right(-30)"),
    ("```\nspeak(\"It's on the sofa.\")\n```", "speak(\"It's on the sofa.\")"),
    ("The user is ahead.\nAction: move_forward(2)\nThat should do it.", "move_forward(2)"),
])
def test_extract_action_tolerates_chat_decoration(reply, expected):
    assert extract_action(reply) == expected


def test_extract_action_reports_the_parse_error():
    with pytest.raises(ActionParseError, match="unknown action 'walk'"):
        extract_action("walk(3)")


# -- the transport: malformed answers, errors, rate limits, timeouts ------------------------------------


def test_malformed_answers_are_retried():
    script = [("raw", b"<html>upstream proxy error</html>"), ("no_choices",), ("raw", b'{"choices": ['),
              ("reply", "move_forward(1)")]
    with FakeChatServer(script) as server:
        agent = _agent(server, max_retries=3)
        agent.reset("Come here.")
        assert agent.act({"rgb": np.zeros((8, 8, 3), np.uint8)}) == "move_forward(1)"
    step = agent.steps[0]
    assert step.requests == 4 and len(step.errors) == 3
    assert all(e.startswith("not a chat completion") for e in step.errors)
    assert "no choices" in step.errors[1]


def test_server_errors_and_rate_limits_are_retried_with_backoff():
    script = [("status", 500), ("status", 429, {"Retry-After": "0.3"}), ("status", 503), ("reply", "move_forward(1)")]
    with FakeChatServer(script) as server:
        agent = _agent(server, max_retries=3, backoff=0.05)
        agent.reset("Come here.")
        assert agent.act({"rgb": np.zeros((8, 8, 3), np.uint8)}) == "move_forward(1)"
    assert agent.steps[0].errors == ["HTTP 500", "HTTP 429", "HTTP 503"]
    t = [r["time"] for r in server.requests]
    assert t[1] - t[0] >= 0.05  # backoff * 2**0
    assert t[2] - t[1] >= 0.3  # Retry-After beats the 0.1 s backoff
    assert t[3] - t[2] >= 0.2  # backoff * 2**2


def test_slow_reply_times_out_and_is_retried():
    with FakeChatServer([("held", "rotate_right(10)"), ("reply", "move_forward(1)")]) as server:
        agent = _agent(server, timeout=0.3, max_retries=1)
        agent.reset("Come here.")
        started = time.monotonic()
        assert agent.act({"rgb": np.zeros((8, 8, 3), np.uint8)}) == "move_forward(1)"
        assert time.monotonic() - started < HOLD_SECONDS / 2  # it did not wait for the held reply
    assert agent.steps[0].errors == ["no reply within 0.3 s"]


def test_persistent_server_errors_raise_naming_the_url():
    with FakeChatServer(default=("status", 500)) as server:
        agent = _agent(server, max_retries=2)
        agent.reset("Come here.")
        with pytest.raises(EndpointError, match=f"{server.url} failed 3 time") as info:
            agent.act({"rgb": np.zeros((8, 8, 3), np.uint8)})
    assert len(server.requests) == 3
    assert info.value.__cause__ is None and info.value.__suppress_context__


def test_client_errors_are_not_retried():
    with FakeChatServer(default=("status", 401)) as server:
        agent = _agent(server, max_retries=3)
        agent.reset("Come here.")
        with pytest.raises(EndpointError, match="refused the request: HTTP 401: test error 401"):
            agent.act({"rgb": np.zeros((8, 8, 3), np.uint8)})
    assert len(server.requests) == 1


def test_unreachable_server_raises_a_clear_error():
    url = f"http://127.0.0.1:{_closed_port()}/v1"
    agent = LLMAgent(base_url=url, api_key="k", model="m", max_retries=1, backoff=0.0, timeout=2.0)
    agent.reset("Come here.")
    with pytest.raises(EndpointError, match=rf"{url} failed 2 time\(s\) \(last: connection failed"):
        agent.act({"rgb": np.zeros((8, 8, 3), np.uint8)})


# -- configuration and the CLI -----------------------------------------------------------------


def test_environment_variables_configure_the_endpoint(monkeypatch):
    with FakeChatServer([("reply", "finish()")]) as server:
        monkeypatch.setenv("OPENAI_BASE_URL", server.url)
        monkeypatch.setenv("OPENAI_API_KEY", "env-key")
        agent = LLMAgent(model="m", backoff=0.0)
        agent.reset("Come here.")
        assert agent.act({"rgb": np.zeros((8, 8, 3), np.uint8)}) == "finish()"
    assert agent.endpoint.base_url == server.url
    assert server.requests[0]["headers"]["authorization"] == "Bearer env-key"


def test_bad_configuration_is_refused(monkeypatch):
    monkeypatch.delenv("OPENAI_API_KEY", raising=False)
    monkeypatch.delenv("OPENAI_BASE_URL", raising=False)
    with pytest.raises(ValueError, match="needs an API key"):
        LLMAgent(model="m")
    with pytest.raises(ValueError, match="http"):
        LLMAgent(base_url="127.0.0.1:8000", model="m")
    with pytest.raises(ValueError, match="timeout"):
        LLMAgent(base_url="http://127.0.0.1:1/v1", model="m", timeout=0)
    with pytest.raises(ValueError, match="history"):
        LLMAgent(base_url="http://127.0.0.1:1/v1", model="m", history=0)
    with pytest.raises(RuntimeError, match="reset"):
        LLMAgent(base_url="http://127.0.0.1:1/v1", model="m").act({"rgb": np.zeros((8, 8, 3), np.uint8)})


def test_cli_runs_episodes_and_writes_the_trace(tmp_path, capsys):
    trace = tmp_path / "trace.jsonl"
    with FakeChatServer([("reply", "hello")] * 3, default=("reply", "rotate_right(45)")) as server:
        rc = main(["--env", ENV_ID, "--base-url", server.url, "--model", "test-vlm", "--episodes", "1",
                   "--seed", "0", "--retries", "0", "--trace", str(trace)])
    out = capsys.readouterr().out
    assert rc == 0 and "test-vlm on Legent/ComeHere-OneRoom-v0: success" in out
    assert "1 of " in out  # the first step fell back after three unparsable replies
    steps = [json.loads(line) for line in trace.read_text().splitlines()]
    assert steps[0]["action"] == NOOP_ACTION and steps[0]["fallback"]
    assert all(s["action"] == "rotate_right(45)" for s in steps[1:])


def test_cli_reports_an_unreachable_endpoint_without_a_traceback(capsys):
    url = f"http://127.0.0.1:{_closed_port()}/v1"
    rc = main(["--base-url", url, "--episodes", "1", "--retries", "1", "--timeout", "2"])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith(f"error: chat endpoint {url} failed 2 time(s)")
    assert "Traceback" not in err
