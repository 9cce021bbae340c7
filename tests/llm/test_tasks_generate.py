"""`legent-gym tasks generate` against a real chat completions server on 127.0.0.1 that
replays replies (tests/chat_server.py), and ``Legent/Custom-v0`` playing the tasks file:
every kept task is completed by the expert, every rejected one says why, and every failure
of the endpoint is one line on stderr with no file written."""

from __future__ import annotations

import json

import gymnasium as gym
import pytest
from gymnasium.utils.env_checker import check_env

from legent_gym.cli import main
from legent_gym.llm.prompts import TASK_PROMPT_VERSION
from legent_gym.tasks import MAX_ACTIONS
from legent_gym.wrappers.expert import ExpertInfo
from tests.chat_server import HOLD_SECONDS, ReplayServer
from tests.conftest import EXAMPLES

SCENE = EXAMPLES / "two_room_furnished.json"
# Object ids of that scene: 0 bed, 12 sofa, 15 armchair, 16 side table, 18 dining table,
# 37 laptop (on the desk), 39 phone (on the chair), 53 vase and 52 book (on the sofa),
# 55 remote (on the coffee table), 58 pear (on the armchair), 60 apple (on side table 16).
GOOD = [
    {"kind": "come", "instruction": "Come here.", "code": "goto_user()"},
    {"kind": "goto", "instruction": "Go to the sofa.", "target": 12, "code": "goto(12)"},
    {"kind": "take", "instruction": "Pick up the laptop on the desk.", "target": 37,
     "code": "goto(37) target(37) interact()"},
    {"kind": "bring", "instruction": "Bring me the phone from the chair.", "target": 39,
     "code": "goto(39) target(39) interact() goto_user()"},
    {"kind": "put", "instruction": "Put the remote on the dining table.", "target": 55, "receptacle": 18,
     "code": "goto(55) target(55) interact() goto(18) target(18) interact()"},
    {"kind": "where", "instruction": "Where is the pear?", "target": 58, "receptacle": 15,
     "code": 'find(58) speak("It\'s on the armchair.")'},
    {"kind": "exist", "instruction": "Is there a vase in the living room?", "target": 53, "receptacle": 12,
     "code": 'find(53) speak("Yes, it is on the sofa.")'},
]
#: LEGENT's own form (kind and objects read off the solution), with the kind and objects expected.
LEGENT_FORM = [
    ("Task: Bring me the laptop on the sofa.; Plan: Go to the laptop, take it, come back.; "
     "Solution: goto(54) target(54) interact() goto_user()", ("bring", 54, None)),
    ('Task: Where is the toy?; Plan: Find it, then answer.; Solution: find(57) speak("It\'s on the coffee table.")',
     ("where", 57, 13)),
    ("Task: Put the phone on the dining table.; Plan: Take it there.; "
     "Solution: goto(56) target(56) interact() goto(18) target(18) interact()", ("put", 56, 18)),
]
#: Each bad task and a phrase its rejection reason must hold.
BAD = [
    ({"kind": "goto", "instruction": "Go to the piano.", "target": 999, "code": "goto(999)"},
     "no object with id 999"),
    ({"kind": "take", "instruction": "Grab the mug.", "target": 64, "code": "goto(64 target(64)"},
     "code: expected ')'"),
    ({"kind": "take", "instruction": "Take the book.", "target": 52, "code": "goto(52) jump()"},
     "unknown function 'jump'"),
    ({"kind": "take", "instruction": "Pick up the bed.", "target": 0, "code": "goto(0) target(0) interact()"},
     "cannot be picked up"),
    ({"kind": "where", "instruction": "Where is the apple?", "target": 60, "receptacle": 0,
      "code": 'find(60) speak("On the bed.")'}, "stands on side table (16), not on 0"),
    ({"kind": "where", "instruction": "Where's the pear?", "target": 58, "receptacle": 15,
      "code": 'find(58) speak("It is on the floor.")'}, "its code fails: the episode ended without success"),
    ({"kind": "bring", "instruction": "Bring me the laptop.", "target": 37,
      "code": "goto(37) target(37) interact()"}, "its code fails"),
    ({"kind": "dance", "instruction": "Dance.", "code": "finish()"}, "not a task: kind"),
    ({"kind": "put", "instruction": "Put the remote down.", "target": 55, "code": "goto(55)"},
     "needs a receptacle"),
    ({"kind": "come", "instruction": "Come here.", "code": "goto_user()"}, "the same instruction twice"),
    ("Task: Bring me the orange on the side table.; Plan: Go to the orange, take it, come back.; "
     "Solution: goto(61) target(61) interact() goto_user()", "its code fails: not done within 25 actions"),
    ("Task: Put the phone on the coffee table.; Plan: Take it there.; "
     "Solution: goto(56) target(56) interact() goto(13) target(13) interact()", "target 56 (phone) is on 13 already"),
    ("just words", "neither a JSON object nor 'Task: ...; Plan: ...; Solution: ...'"),
    ("Task: Dance.; Plan: Dance.; Solution: speak(\"la\")", "cannot tell the kind of task"),
    ("Task: Take the mug.; Plan: Grab it.; Solution: grab()", "nothing is approached before the first interaction"),
]


def _generate(url, out, *extra, n="20", retries="0", timeout="5"):
    return main(["tasks", "generate", str(SCENE), "--n", n, "--llm-base-url", url, "--model", "test-llm",
                 "--timeout", timeout, "--retries", retries, "--out", str(out), *extra])


def _lines(path):
    return [json.loads(line) for line in path.read_text().splitlines()]


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    out = tmp_path_factory.mktemp("tasks") / "tasks.jsonl"
    reply = json.dumps({"tasks": GOOD + [text for text, _ in LEGENT_FORM] + [task for task, _ in BAD]})
    with ReplayServer([("reply", reply)]) as server:
        assert _generate(server.url, out, n="30") == 0
    return out, server.requests


def test_the_llm_sees_the_object_table_and_writes_json(generated):
    _, requests = generated
    assert len(requests) == 1
    body = requests[0]["body"]
    assert body["response_format"] == {"type": "json_object"}
    system = body["messages"][0]["content"]
    assert "37 | laptop | " in system and "| desk (5) | yes" in system  # id | name | x y z | on | pickable
    assert "0 | bed | " in system and "| floor | no" in system
    assert "Write 30 different tasks" in system


def test_valid_tasks_are_kept_and_bad_ones_rejected_with_their_reason(generated):
    out, _ = generated
    header, *records = _lines(out)
    assert header["format"] == "legent-gym-tasks" and header["prompt_version"] == TASK_PROMPT_VERSION
    assert [0, "bed"] in header["objects"]
    assert len(records) == len(GOOD) + len(LEGENT_FORM) + len(BAD)  # in the reply's order
    kept, rejected = records[:len(GOOD) + len(LEGENT_FORM)], records[len(GOOD) + len(LEGENT_FORM):]
    assert all(r["status"] == "kept" for r in kept), [r.get("reason") for r in kept]
    assert [r["kind"] for r in kept[:len(GOOD)]] == [t["kind"] for t in GOOD]
    assert [(r["kind"], r["target"], r["receptacle"]) for r in kept[len(GOOD):]] == [e for _, e in LEGENT_FORM]
    for r in kept:
        assert 1 <= r["actions"] <= MAX_ACTIONS and 1 <= r["expert_actions"] <= MAX_ACTIONS
    for record, (_, phrase) in zip(rejected, BAD):
        assert record["status"] == "rejected" and phrase in record["reason"], (record, phrase)


def test_custom_env_plays_the_file_and_the_expert_completes_every_kept_task(generated):
    out, _ = generated
    kept = [r for r in _lines(out)[1:] if r["status"] == "kept"]
    env = ExpertInfo(gym.make("Legent/Custom-v0", scene=str(SCENE), tasks=str(out),
                              task_options={"order": "sequential"}, width=32, height=32))
    assert env.spec.max_episode_steps == MAX_ACTIONS
    done = 0
    for record in kept:  # in the file's order
        obs, info = env.reset()
        assert obs["instruction"] == record["instruction"] and not info["success"]
        assert info["task"]["target"] == (-1 if record["target"] is None else record["target"])  # -1: none
        for _ in range(MAX_ACTIONS):
            obs, reward, terminated, truncated, info = env.step(info["expert_action"])
            if terminated or truncated:
                break
        assert info["success"] and reward == 1.0, record
        done += 1
    assert done == len(kept) == len(GOOD) + len(LEGENT_FORM)  # 100%
    env.close()


def test_custom_env_passes_check_env_and_draws_tasks_by_seed(generated):
    out, _ = generated
    for action_type in ("text", "continuous"):
        env = gym.make("Legent/Custom-v0", scene=str(SCENE), tasks=str(out), action_type=action_type,
                       width=32, height=32)
        check_env(env.unwrapped, skip_render_check=True)
        env.close()
    env = gym.make("Legent/Custom-v0", scene=str(SCENE), tasks=str(out), width=32, height=32)
    first = [env.reset(seed=s)[0]["instruction"] for s in range(12)]
    again = [env.reset(seed=s)[0]["instruction"] for s in range(12)]
    assert first == again and len(set(first)) > 2  # seeded: the same task; several tasks drawn
    env.close()


def test_custom_env_pickles_and_its_spec_round_trips(generated):
    import pickle

    out, _ = generated
    env = gym.make("Legent/Custom-v0", scene=str(SCENE), tasks=str(out), width=32, height=32)
    obs, _ = env.reset(seed=4)
    clone = pickle.loads(pickle.dumps(env))
    assert clone.reset(seed=4)[0]["instruction"] == obs["instruction"]
    remade = gym.make(gym.envs.registration.EnvSpec.from_json(env.spec.to_json()))
    assert remade.reset(seed=4)[0]["instruction"] == obs["instruction"]
    for e in (env, clone, remade):
        e.close()


def test_collect_records_expert_episodes_of_the_generated_tasks(generated, tmp_path, capsys):
    out, _ = generated
    kwargs = json.dumps({"scene": str(SCENE), "tasks": str(out)})
    assert main(["collect", "Legent/Custom-v0", "--episodes", "4", "--out", str(tmp_path / "data"), "--format",
                 "legent", "--env-kwargs", kwargs, "--quiet"]) == 0
    assert "0 failed attempts, success rate 100.0%" in capsys.readouterr().out


def test_custom_env_refuses_another_scene_and_a_missing_one(generated, tmp_path):
    out, _ = generated
    with pytest.raises(ValueError, match="give scene="):
        gym.make("Legent/Custom-v0", tasks=str(out))
    env = gym.make("Legent/Custom-v0", scene=str(EXAMPLES / "one_room.json"), tasks=str(out))
    with pytest.raises(ValueError, match="written for another scene"):
        env.reset(seed=0)
    empty = tmp_path / "none.jsonl"
    empty.write_text(out.read_text().splitlines()[0] + "\n")
    with pytest.raises(ValueError, match="no kept task"):
        gym.make("Legent/Custom-v0", scene=str(SCENE), tasks=str(empty))


def _one_line_error(capsys, *needles):
    err = capsys.readouterr().err
    assert err.startswith("legent-gym: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err


FAILURES = {
    "HTTP 500": ([("status", 500)], "failed 1 time(s) (last: HTTP 500)"),
    "not JSON twice": ([("reply", "Sure! Here are some tasks."), ("reply", "Task: come; Plan: walk")],
                       "sent an invalid TaskReply twice (last: the reply is not JSON"),
    "no tasks twice": ([("reply", '{"tasks": []}'), ("reply", '{"tasks": []}')], "invalid TaskReply twice"),
    "wrong type twice": ([("reply", '{"tasks": "come"}'), ("reply", '{"tasks": 3}')], "tasks: Input should be"),
    "empty choices": ([("empty_choices",)], "no choices in the response"),
    "HTTP 404": ([("status", 404, {}, "no such model")], "refused the request: HTTP 404: no such model"),
    "5 MB reply": ([("big", 5_000_000)], "reply over 1000000 bytes"),
}


@pytest.mark.parametrize("case", FAILURES)
def test_endpoint_failures_are_one_line_and_write_nothing(tmp_path, capsys, case):
    script, needle = FAILURES[case]
    with ReplayServer(script) as server:
        assert _generate(server.url, tmp_path / "tasks.jsonl") == 2
    _one_line_error(capsys, needle)
    assert list(tmp_path.iterdir()) == []


def test_an_invalid_reply_then_a_valid_one_gives_the_file(tmp_path, capsys):
    with ReplayServer([("reply", "no"), ("reply", json.dumps({"tasks": GOOD[:2]}))]) as server:
        assert _generate(server.url, tmp_path / "tasks.jsonl", n="2") == 0
    assert "not valid" in server.requests[1]["body"]["messages"][-1]["content"]
    records = _lines(tmp_path / "tasks.jsonl")[1:]
    assert [r["status"] for r in records] == ["kept", "kept"]
    assert "wrote" in capsys.readouterr().out


def test_a_timeout_is_honoured(tmp_path, capsys):
    import time

    with ReplayServer([("held", json.dumps({"tasks": GOOD[:1]}))]) as server:
        started = time.monotonic()
        assert _generate(server.url, tmp_path / "tasks.jsonl", timeout="0.5") == 2
        # Far above the 0.5 s it takes, far below the held reply's HOLD_SECONDS.
        assert time.monotonic() - started < HOLD_SECONDS / 2
    _one_line_error(capsys, "no reply within 0.5 s")
    assert list(tmp_path.iterdir()) == []
