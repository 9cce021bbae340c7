"""Vector envs as users make them, with the real clients: Gymnasium's ``make_vec`` (async and
sync) and stable-baselines3's ``SubprocVecEnv`` return, for the same seeds, every observation
key of every step equal to single envs', across an automatic reset; and a ``make_vec`` after
a render in the parent never hangs (legent_gym/envs/text_space.py, legent_gym/world/render.py).

The async clients run in a fresh Python process, as a user's script does: Python's default
``fork`` start method (what ``make_vec(..., vectorization_mode="async")`` uses unless told
otherwise) is only safe from a process that has not rendered, and this test process may have.
"""

from __future__ import annotations

import copy
import importlib.util
import multiprocessing
import os
import pickle
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector.utils import (
    create_shared_memory,
    read_from_shared_memory,
    write_to_shared_memory,
)

import legent_gym  # noqa: F401
from legent_gym.envs.action_spaces import speech_space
from legent_gym.envs.text_space import TextView, VectorSafeText
from legent_gym.world.render import FORK_AFTER_GL

REPO = Path(__file__).resolve().parents[2]
ENV_ID = "Legent/ComeHere-OneRoom-v0"
KWARGS = {"width": 32, "height": 32}
#: Both envs' actions, step by step: env 0 finishes at step 2 and env 1 at step 4, so each
#: resets itself once (Gymnasium's next-step autoreset: the step after the last one
#: returns the reset observation and ignores its action).
ACTIONS = [
    ["move_forward(0.5)", "rotate_right(30)"],
    ["finish()", 'speak("Where are you?")'],
    ["rotate_right(30)", "move_forward(0.5), rotate_right(-30)"],
    ["move_forward(0.5)", "finish()"],
    ['speak("On my way.")', "rotate_right(30)"],
    ["rotate_right(-30)", "move_forward(0.5)"],
]
#: The seconds a child script may take (a hang fails the test instead of blocking the suite).
DEADLINE = 240

_VECTOR_SCRIPT = """
import pickle, sys
sys.path.insert(0, {repo!r})
from tests.envs.test_vector_clients import gymnasium_runs, sb3_runs

if __name__ == "__main__":
    result = {{"async": gymnasium_runs("async")}}
    if sys.argv[2] == "sb3":
        result["sb3"] = sb3_runs()
    with open(sys.argv[1], "wb") as f:
        pickle.dump(result, f)
"""

_AFTER_RENDER_SCRIPT = """
import gymnasium as gym
import numpy as np
import legent_gym

ENV_ID, KWARGS = {env_id!r}, {kwargs!r}


def first_instructions(**vector_kwargs):
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="async", vector_kwargs=vector_kwargs, **KWARGS)
    try:
        return envs.reset(seed=0)[0]["instruction"]
    finally:
        envs.close()


if __name__ == "__main__":
    env = gym.make(ENV_ID, **KWARGS)
    assert env.reset(seed=0)[0]["rgb"].any()  # the parent renders first
    try:
        first_instructions()
    except RuntimeError as error:
        print("FORK REFUSED:", error)
    else:
        print("FORK RAN")
    print("FORKSERVER:", list(first_instructions(context="forkserver")))
    env.close()
"""


def gymnasium_runs(mode: str) -> list:
    """``gym.make_vec(ENV_ID, 2, vectorization_mode=mode)``: the reset observation (seeds 0
    and 1), then (obs, reward, terminated, truncated) of every step of :data:`ACTIONS`."""
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode=mode, **KWARGS)
    try:
        runs = [envs.reset(seed=0)[0]]
        for actions in ACTIONS:
            runs.append(envs.step(np.array(actions, dtype=object))[:4])
    finally:
        envs.close()
    return runs


def sb3_runs() -> list:
    """The same through stable-baselines3's ``SubprocVecEnv``: (obs, reward, done) per step."""
    from stable_baselines3.common.vec_env import SubprocVecEnv

    # "fork" (the script has not rendered): SB3's default, forkserver, would import the
    # script again in its server and in every worker, seconds each, for the same data path.
    envs = SubprocVecEnv([lambda: gym.make(ENV_ID, **KWARGS)] * 2, start_method="fork")
    try:
        envs.seed(0)
        runs = [envs.reset()]
        for actions in ACTIONS:
            obs, reward, done, _ = envs.step(np.array(actions, dtype=object))
            runs.append((obs, reward, done))
    finally:
        envs.close()
    return runs


def _run_script(tmp_path, source: str, *args: str) -> str:
    """Run ``source`` as a user's script (``python script.py args``); its standard output."""
    script = tmp_path / "user_script.py"
    script.write_text(textwrap.dedent(source))
    # A session of its own, so that a hang kills the workers too, not only the script.
    proc = subprocess.Popen([sys.executable, str(script), *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, cwd=tmp_path, start_new_session=True)
    try:
        stdout, stderr = proc.communicate(timeout=DEADLINE)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        stdout, stderr = proc.communicate()
        pytest.fail(f"the script hung (killed after {DEADLINE} s): {stdout[-2000:]} {stderr[-2000:]}")
    assert proc.returncode == 0, stderr[-4000:]
    return stdout


def _single_env_runs(autoreset_same_step: bool = False) -> list[list]:
    """For env i (seed i): the reset observation, then per step (obs, reward, terminated,
    truncated), resetting after an episode's end as the vector env does: on the next step
    (Gymnasium), or at once, in place of the last observation (stable-baselines3)."""
    runs = []
    for i in range(2):
        env = gym.make(ENV_ID, **KWARGS)
        try:
            run = [env.reset(seed=i)[0]]
            ended = False
            for actions in ACTIONS:
                if ended and not autoreset_same_step:
                    run.append((env.reset()[0], 0.0, False, False))
                    ended = False
                    continue
                obs, reward, terminated, truncated, _ = env.step(actions[i])
                ended = terminated or truncated
                if ended and autoreset_same_step:
                    obs = env.reset()[0]
                run.append((obs, reward, terminated, truncated))
        finally:
            env.close()
        runs.append(run)
    return runs


def _assert_same_obs(batched: dict, single: dict, env_index: int, where: str) -> None:
    assert set(batched) == set(single), where
    for key, value in single.items():
        got = batched[key][env_index]
        if isinstance(value, str):
            assert isinstance(got, str) and got == value, f"{where}: {key} {got!r} != {value!r}"
        else:
            assert np.array_equal(got, value), f"{where}: {key} differs"


def _assert_runs_match(vector_runs: list, single_runs: list[list], autoreset_same_step: bool = False) -> None:
    """``vector_runs``: the reset observation, then per step a tuple starting (obs, reward,
    terminated[, truncated]) over both envs."""
    for i, run in enumerate(single_runs):
        _assert_same_obs(vector_runs[0], run[0], i, f"env {i} reset")
        for t, (step, (obs, reward, terminated, truncated)) in enumerate(zip(vector_runs[1:], run[1:], strict=True)):
            where = f"env {i} step {t + 1}"
            _assert_same_obs(step[0], obs, i, where)
            assert step[1][i] == pytest.approx(reward), where
            assert bool(step[2][i]) == (terminated or (truncated and autoreset_same_step)), where
    # The episodes did end and restart (the autoreset was exercised), and the text is real.
    assert [bool(step[2][0]) for step in vector_runs[1:]][:4] == [False, True, False, False]
    assert all(run[0]["instruction"].strip() for run in single_runs)


def test_vector_safe_text_reads_what_is_written_after_the_read():
    space = speech_space(12)
    assert isinstance(space, VectorSafeText) and space == gym.spaces.Text(12, min_length=0, charset=space.characters)
    memory = create_shared_memory(space, n=2, ctx=multiprocessing)
    view = read_from_shared_memory(space, memory, n=2)
    assert isinstance(view, TextView) and tuple(view) == ("", "")
    write_to_shared_memory(space, 1, "It's here!", memory)
    write_to_shared_memory(space, 0, "Über, café", memory)
    assert view == ("Über, café", "It's here!") and view[1] == "It's here!" and len(view) == 2
    copied = copy.deepcopy({"message": view})["message"]
    assert type(copied) is tuple and copied == ("Über, café", "It's here!")
    write_to_shared_memory(space, 0, "", memory)
    assert view[0] == "" and copied[0] == "Über, café"
    assert pickle.loads(pickle.dumps(space)) == space and type(pickle.loads(pickle.dumps(space))) is VectorSafeText
    with pytest.raises(ValueError, match="max_length=12"):
        write_to_shared_memory(space, 0, "x" * 13, memory)


def test_sync_make_vec_equals_single_envs():
    _assert_runs_match(gymnasium_runs("sync"), _single_env_runs())


def test_async_make_vec_and_sb3_subproc_equal_single_envs(tmp_path):
    clients = "sb3" if importlib.util.find_spec("stable_baselines3") else "gymnasium"
    _run_script(tmp_path, _VECTOR_SCRIPT.format(repo=str(REPO)),
                str(tmp_path / "runs.pkl"), clients)
    with open(tmp_path / "runs.pkl", "rb") as f:
        result = pickle.load(f)
    observations = [result["async"][0]] + [step[0] for step in result["async"][1:]]
    assert all(type(obs["instruction"]) is tuple for obs in observations)  # as the sync vector env's
    _assert_runs_match(result["async"], _single_env_runs())
    if clients == "sb3":
        _assert_runs_match(result["sb3"], _single_env_runs(autoreset_same_step=True), autoreset_same_step=True)


def test_make_vec_after_a_render_in_the_parent_refuses_fork_and_runs_with_forkserver(tmp_path):
    out = _run_script(tmp_path, _AFTER_RENDER_SCRIPT.format(env_id=ENV_ID, kwargs=KWARGS))
    assert f"FORK REFUSED: {FORK_AFTER_GL}" in out, out
    instructions = out.split("FORKSERVER:", 1)[1]
    assert "come here" in instructions.lower(), out
