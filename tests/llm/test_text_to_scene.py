"""`legent-gym generate --prompt` against a real chat completions server on 127.0.0.1 that
replays replies (tests/chat_server.py): every case ends in a scene with its plan beside it
or in one line on stderr (exit 2), with no partial files, in bounded time."""

from __future__ import annotations

import json
import time

import gymnasium as gym
import pytest

from legent_gym.cli import main
from legent_gym.llm.prompts import SCENE_PLAN_PROMPT_VERSION, scene_plan_messages
from legent_gym.world.generation import check_house
from legent_gym.world.scene import load_scene
from tests.chat_server import HOLD_SECONDS, ReplayServer, closed_port

PLAN = {"version": 1, "name": "reading flat", "rooms": [
    {"name": "living", "type": "living room", "size": 18, "objects": [
        {"name": "sofa", "relations": [{"kind": "against_wall"}]},
        {"name": "armchair", "relations": [{"kind": "near", "target": "bookshelf"}]},
        {"name": "bookshelf", "relations": [{"kind": "against_wall"}]},
        {"name": "book", "count": 2, "on": "bookshelf"}]},
    {"name": "kitchen", "type": "kitchen", "size": 10, "objects": [
        {"name": "fridge"}, {"name": "counter", "asset": "kitchen counter"}, {"name": "apple", "on": "counter"}]}],
    "doors": [["living", "kitchen"]]}


def _run(server_url, tmp_path, *extra, timeout="5", retries="0"):
    return main(["generate", "--prompt", "a small flat with a kitchen and a reading corner", "--llm-base-url",
                 server_url, "--model", "test-llm", "--timeout", timeout, "--retries", retries, "--seed", "1",
                 "--out", str(tmp_path / "house.json"), *extra])


def _files(tmp_path) -> list[str]:
    return sorted(p.name for p in tmp_path.iterdir())


def _one_line_error(capsys, *needles):
    err = capsys.readouterr().err
    assert err.startswith("legent-gym: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err
    return err


def test_a_valid_plan_gives_a_scene_and_the_plan_beside_it(tmp_path, capsys):
    with ReplayServer([("reply", json.dumps(PLAN))]) as server:
        assert _run(server.url, tmp_path, "--map", str(tmp_path / "house.png")) == 0
    assert _files(tmp_path) == ["house.json", "house.plan.json", "house.png"]
    scene = load_scene(tmp_path / "house.json")
    assert check_house(scene) == [] and len(scene.rooms) == 2
    assert json.loads((tmp_path / "house.plan.json").read_text())["rooms"][0]["name"] == "living"
    request = server.requests[0]["body"]
    assert request["response_format"] == {"type": "json_object"} and request["model"] == "test-llm"
    assert "a small flat with a kitchen and a reading corner" in request["messages"][-1]["content"]
    assert "kitchen_counter" in request["messages"][0]["content"]  # the library's categories are listed
    # The saved plan rebuilds the same house without the LLM.
    capsys.readouterr()
    assert main(["generate", "--plan", str(tmp_path / "house.plan.json"), "--seed", "1", "--out",
                 str(tmp_path / "again.json")]) == 0
    assert (tmp_path / "again.json").read_text() == (tmp_path / "house.json").read_text()
    # An env takes the scene.
    env = gym.make("Legent/ComeHere-OneRoom-v0", scene=str(tmp_path / "house.json"), width=32, height=32)
    obs, _ = env.reset(seed=0)
    assert obs["rgb"].shape == (32, 32, 3) and obs["rgb"].std() > 1
    env.close()


@pytest.mark.parametrize("bad, error", [("I'd suggest a cosy flat!", "not JSON"),
                                        ('{"rooms": [{"name": "a", "type": 3, "size": "big"}]}', "rooms.0")])
def test_an_invalid_reply_is_sent_back_once(tmp_path, bad, error):
    with ReplayServer([("reply", bad), ("reply", json.dumps(PLAN))]) as server:
        assert _run(server.url, tmp_path) == 0
    feedback = server.requests[1]["body"]["messages"]
    assert feedback[-2] == {"role": "assistant", "content": bad}
    assert error in feedback[-1]["content"]
    assert _files(tmp_path) == ["house.json", "house.plan.json"]


@pytest.mark.parametrize("bad, error", [("{not json", "not JSON"),
                                        ('{"rooms": [{"name": "a", "type": ["kitchen"]}]}', "rooms.0.type"),
                                        ('{"rooms": []}', "rooms: List should have at least 1 item")])
def test_invalid_replies_twice_are_one_line_and_no_files(tmp_path, capsys, bad, error):
    with ReplayServer(default=("reply", bad)) as server:
        assert _run(server.url, tmp_path) == 2
    assert len(server.requests) == 2
    _one_line_error(capsys, "sent an invalid ScenePlan twice", error)
    assert _files(tmp_path) == []


def test_unknown_assets_are_mapped_or_dropped(tmp_path, capsys):
    plan = {"rooms": [{"name": "den", "type": "reading nook", "objects": [
        {"name": "couch", "asset": "chesterfield couch"}, {"name": "robot", "asset": "robot butler"}]}]}
    with ReplayServer([("reply", json.dumps(plan))]) as server:
        assert _run(server.url, tmp_path) == 0
    out = capsys.readouterr().out
    assert "mapped 'chesterfield couch' to the library category 'sofa'" in out
    assert "warning: dropped den/robot: 'robot butler'" in out and "type 'reading nook' is not known" in out
    assert _files(tmp_path) == ["house.json", "house.plan.json"]


def test_impossible_relations_are_printed(tmp_path, capsys):
    plan = {"rooms": [{"name": "bath", "type": "bathroom", "size": 5, "objects": [
        {"name": "toilet", "relations": [{"kind": "far", "target": "sink"}]}, {"name": "sink"},
        {"name": "wardrobe", "count": 5}]}]}
    with ReplayServer([("reply", json.dumps(plan))]) as server:
        assert _run(server.url, tmp_path) == 0
    out = capsys.readouterr().out
    assert "unmet: bath/wardrobe: no room for a wardrobe" in out
    assert check_house(load_scene(tmp_path / "house.json")) == []


@pytest.mark.parametrize("behaviour, needles", [
    (("empty_choices",), ["failed 1 time(s)", "no choices"]),
    (("status", 500), ["failed 1 time(s)", "HTTP 500"]),
    (("status", 404, {}, "model test-llm not found"), ["refused the request: HTTP 404: model test-llm not found"]),
    (("raw", b"<html>gateway</html>"), ["not a chat completion"]),
    (("big", 5_000_000), ["over 1000000 bytes"]),
])
def test_endpoint_failures_are_one_line(tmp_path, capsys, behaviour, needles):
    with ReplayServer(default=behaviour) as server:
        started = time.monotonic()
        assert _run(server.url, tmp_path) == 2
        assert time.monotonic() - started < 10
    _one_line_error(capsys, server.url, *needles)
    assert _files(tmp_path) == []


def test_retries_then_a_valid_plan(tmp_path):
    with ReplayServer([("status", 503), ("reply", json.dumps(PLAN))]) as server:
        assert _run(server.url, tmp_path, retries="1") == 0
    assert len(server.requests) == 2 and _files(tmp_path) == ["house.json", "house.plan.json"]


def test_a_slow_endpoint_times_out(tmp_path, capsys):
    with ReplayServer(default=("held", json.dumps(PLAN))) as server:
        started = time.monotonic()
        assert _run(server.url, tmp_path, timeout="0.5") == 2
        assert time.monotonic() - started < HOLD_SECONDS / 2  # far above the 0.5 s it takes
    _one_line_error(capsys, "no reply within 0.5 s")
    assert _files(tmp_path) == []


def test_unreachable_endpoint_and_missing_flags(tmp_path, capsys):
    url = f"http://127.0.0.1:{closed_port()}/v1"
    assert _run(url, tmp_path) == 2
    _one_line_error(capsys, url, "connection failed")
    assert main(["generate", "--prompt", "a flat", "--out", str(tmp_path / "h.json")]) == 2
    _one_line_error(capsys, "--prompt needs --model")
    assert main(["generate", "--prompt", "a flat", "--plan", "p.json", "--model", "m",
                 "--out", str(tmp_path / "h.json")]) == 2
    _one_line_error(capsys, "not both")
    assert _files(tmp_path) == []


def test_the_prompt_is_versioned_and_lists_the_library():
    messages = scene_plan_messages("a bedsit")
    assert SCENE_PLAN_PROMPT_VERSION == 1
    assert [m["role"] for m in messages] == ["system", "user"]
    for word in ("against_wall", "in_front_of", "sofa", "apple", "living room", '"version": 1'):
        assert word in messages[0]["content"]
