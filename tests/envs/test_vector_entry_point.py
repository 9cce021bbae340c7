"""The registered vector entry point (legent_gym/envs/shared_vector.py): ``gym.make_vec(id, N,
vectorization_mode="vector_entry_point")`` returns the same observations, rewards,
terminations, truncations and infos as Gymnasium's ``SyncVectorEnv`` of the same seeds and
actions (every key and type, the infos' key order too), across autoresets and truncations,
partial and unseeded resets; passes Gymnasium's ``check_environments_match`` against it;
raises a worker's error with its traceback; and leaves no process or ``/dev/shm`` entry
behind, closed, killed or orphaned.
"""

from __future__ import annotations

import copy
import gc
import os
import pickle
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import gymnasium as gym
import numpy as np
import psutil
import pytest
from gymnasium.utils.env_checker import data_equivalence
from gymnasium.vector import AutoresetMode

import legent_gym  # noqa: F401
from legent_gym.envs.shared_vector import (
    LazyInfos,
    SharedMemoryVectorEnv,
    WorkerError,
    _leaves,
    worker_pids,
)

ENV_ID = "Legent/ComeHere-OneRoom-v0"
SMALL = {"width": 32, "height": 32}
#: Three envs' text actions per step: env 0 finishes at step 2 (and resets at step 3), env
#: 2 speaks and turns; with max_episode_steps=4 env 1 and 2 are truncated at step 4.
ACTIONS = [
    ["move_forward(0.5)", "rotate_right(30)", 'speak("Where are you?")'],
    ["finish()", "move_forward(0.5), rotate_right(-30)", "rotate_right(30)"],
    ["rotate_right(30)", "rotate_down(10)", "not an action"],
    ["move_forward(0.5)", "grab()", "move_forward(1)"],
    ['speak("On my way.")', "rotate_right(30)", "finish()"],
    ["rotate_right(-30)", "move_forward(0.5)", "rotate_right(10)"],
]


def _ours(envs: SharedMemoryVectorEnv) -> list[str]:
    """The entries the vector env has in /dev/shm while it is open: its named semaphores
    (the shared batch is an unlinked file from the start)."""
    channel = envs._channel
    return [f"sem.{sem._semlock.name.lstrip('/')}" for sem in (*channel.go, channel.lock, channel.all_in)]


def _assert_shm_gone(names: list[str], seconds: float = 0.0) -> None:
    deadline = time.monotonic() + seconds
    while (left := [n for n in names if os.path.exists(f"/dev/shm/{n}")]) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not left, f"left in /dev/shm: {left}"
    assert not [n for n in os.listdir("/dev/shm") if n.startswith(f"pym-{os.getpid()}-")]


def _same(a, b, where: str) -> None:
    assert data_equivalence(a, b, exact=True), f"{where}: {a!r} != {b!r}"
    if isinstance(a, dict):
        assert list(a) == list(b), f"{where}: key order {list(a)} != {list(b)}"
        for key in a:
            _same(a[key], b[key], f"{where}[{key!r}]")


def _pair(n: int = 3, **kwargs):
    ours = gym.make_vec(ENV_ID, num_envs=n, vectorization_mode="vector_entry_point", **SMALL, **kwargs)
    sync = gym.make_vec(ENV_ID, num_envs=n, vectorization_mode="sync", **SMALL, **kwargs)
    return ours, sync


def test_make_vec_returns_it_for_every_id():
    for env_id, spec in gym.registry.items():
        if env_id.startswith("Legent/"):
            assert spec.vector_entry_point == "legent_gym.envs.shared_vector:make_vector", env_id
    envs = gym.make_vec(ENV_ID, num_envs=2, **SMALL)  # no mode: Gymnasium prefers the entry point
    try:
        assert isinstance(envs, SharedMemoryVectorEnv) and envs.num_envs == 2
        assert envs.metadata["autoreset_mode"] is AutoresetMode.NEXT_STEP
        assert envs.spec.kwargs["vectorization_mode"] == "vector_entry_point"
        assert envs.env_id == ENV_ID and envs.env_kwargs["max_episode_steps"] == 25
        assert envs.single_observation_space == gym.make(ENV_ID, **SMALL).observation_space
        assert envs.call("spec")[0].max_episode_steps == 25
    finally:
        envs.close()
    two = gym.make_vec("Legent/GoTo-TwoRoom-v0", num_envs=1, vectorization_mode="vector_entry_point", **SMALL)
    try:
        assert two.env_id == "Legent/GoTo-TwoRoom-v0"
        assert two.get_attr("layout") == ("TwoRoom",)
    finally:
        two.close()


def test_same_results_as_sync_vector_env():
    """Seeded and unseeded resets, an autoreset (env 0), truncations (max_episode_steps=4),
    a partial reset with reset_mask: every return value equal, types and key order too."""
    ours, sync = _pair(max_episode_steps=4)
    try:
        _same(ours.reset(seed=7), sync.reset(seed=7), "reset")
        terminated, truncated = np.zeros(3, dtype=bool), np.zeros(3, dtype=bool)
        for t, actions in enumerate(ACTIONS):
            got, want = ours.step(np.array(actions, dtype=object)), sync.step(np.array(actions, dtype=object))
            _same(got, want, f"step {t + 1}")
            terminated |= got[2]
            truncated |= got[3]
        assert terminated[0] and truncated.any() and (terminated | truncated).all(), "every episode ended"
        assert want[4]["task"]["name"][0] == "ComeHere" and want[0]["instruction"][0].strip()
        mask = np.array([False, True, True])
        _same(ours.reset(seed=[None, 11, 12], options={"reset_mask": mask.copy()}),
              sync.reset(seed=[None, 11, 12], options={"reset_mask": mask.copy()}), "partial reset")
        _same(ours.step(("rotate_right(20)",) * 3), sync.step(("rotate_right(20)",) * 3), "after the partial reset")
        _same(ours.reset(), sync.reset(), "unseeded reset")
        _same(ours.step(("move_forward(0.3)",) * 3), sync.step(("move_forward(0.3)",) * 3), "after it")
        with pytest.raises(ValueError, match="length must match num_envs=3"):
            ours.reset(seed=[1, 2])
        with pytest.raises(TypeError, match="reset_mask"):
            ours.reset(options={"reset_mask": [True, False, True]})
    finally:
        ours.close()
        sync.close()


def test_workers_with_helpers_stage_episodes_while_they_wait():
    """With helpers, a worker sets up its next episode in the time it waits for the next
    step (Episode.stage, not after its own steps): the same results as SyncVectorEnv without
    helpers, and unseeded resets into new houses that were staged."""
    ours = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", max_episode_steps=3,
                        helpers=1, **SMALL)
    sync = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="sync", max_episode_steps=3, **SMALL)
    try:
        assert ours.get_attr("stage_after_step") == (False, False)
        _same(ours.reset(seed=3), sync.reset(seed=3), "reset")
        for t in range(16):  # five episodes each (an autoreset step after every third step)
            time.sleep(0.1)  # the workers wait: their helpers answer, they stage
            actions = (("rotate_right(30)", "move_forward(0.4)"), ("move_forward(0.4)", "rotate_right(-30)"))[t % 2]
            _same(ours.step(actions), sync.step(actions), f"step {t + 1}")
        staged = [episode.episodes_staged for episode in ours.get_attr("episode")]
        assert min(staged) >= 2, staged
    finally:
        ours.close()
        sync.close()


def test_sampled_continuous_actions_match_sync_and_stay_in_the_spaces():
    """Gymnasium's vector checks as they apply: sampled Dict actions of the batched action
    space over autoresets (``check_environments_match``'s loop, whose own asserts are for a
    single env), observations in the batched observation space, arrays not reused from one
    step to the next (``check_returned_data_not_reused``), renders equal."""
    ours, sync = _pair(2, action_type="continuous", max_episode_steps=5, render_mode="rgb_array")
    try:
        assert ours.action_space == sync.action_space and ours.observation_space == sync.observation_space
        sync.action_space.seed(3)
        _same(ours.reset(seed=3), sync.reset(seed=3), "reset")
        _same(ours.render(), sync.render(), "render")
        previous = None
        for t in range(12):
            action = sync.action_space.sample()
            got = ours.step(action)
            _same(got, sync.step(action), f"step {t + 1}")
            assert ours.observation_space.contains(got[0]), f"step {t + 1}"
            assert previous is None or got[0]["rgb"] is not previous and not np.shares_memory(got[0]["rgb"], previous)
            previous = got[0]["rgb"]
        _same(ours.render(), sync.render(), "render")
        assert ours.render()[0].shape == (256, 256, 3)
    finally:
        ours.close()
        sync.close()


def test_copy_false_views_and_attributes():
    views = SharedMemoryVectorEnv(ENV_ID, 2, copy=False, **SMALL)
    try:
        obs, _ = views.reset(seed=0)
        first = obs["rgb"].copy()
        views.step(("rotate_right(90)", "rotate_right(90)"))
        assert not np.array_equal(obs["rgb"], first)  # the shared batch itself
        views.set_attr("reward_type", ["dense", "dense"])
        assert views.get_attr("reward_type") == ("dense", "dense")
    finally:
        views.close()


def test_lazy_infos_hold_the_same_as_sync_when_read_later():
    """lazy_infos=True (through make_vec): each step's infos, read only after later steps,
    equal the sync vector env's of that step; copies and pickles are plain dicts."""
    ours = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", lazy_infos=True,
                        max_episode_steps=3, **SMALL)
    sync = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="sync", max_episode_steps=3, **SMALL)
    try:
        got, want = [ours.reset(seed=5)[1]], [sync.reset(seed=5)[1]]
        for actions in ACTIONS[:5]:
            got.append(ours.step(actions[:2])[4])
            want.append(sync.step(actions[:2])[4])
        for t, (lazy, plain) in enumerate(zip(got, want)):
            assert isinstance(lazy, LazyInfos) and isinstance(lazy, dict)
            _same(lazy.copy(), plain, f"step {t}")
            assert list(lazy) == list(plain) and len(lazy) == len(plain) and "_task" in lazy
            assert type(pickle.loads(pickle.dumps(lazy))) is dict and type(copy.deepcopy(lazy)) is dict
        assert list(got[3]["n_actions"]) == [0, 3]  # env 1 truncated at step 3: read two steps later
    finally:
        ours.close()
        sync.close()


def _row(data, k: int):
    """Env ``k``'s part of batched data (observations or infos; masks dropped)."""
    if isinstance(data, dict):
        return {key: _row(value, k) for key, value in data.items() if not key.startswith("_")}
    return data[k]


def test_send_recv_returns_each_envs_own_episode():
    """EnvPool-style: 3 envs, recv() returns the first 2 done, send() steps those; each
    env's observations, rewards, ends and infos, in whatever batches they came, are its
    own run of a one-env sync vector env with its seed, across autoresets."""
    steps = {i: [ACTIONS[t][i] for t in range(len(ACTIONS))] for i in range(3)}
    envs = SharedMemoryVectorEnv(ENV_ID, 3, batch_size=2, max_episode_steps=3, **SMALL)
    got: dict[int, list] = {i: [] for i in range(3)}
    try:
        with pytest.raises(RuntimeError, match="nothing sent"):
            envs.recv()
        envs.async_reset(seed=7)
        with pytest.raises(RuntimeError, match="recv\\(\\) it before step"):
            envs.step(("finish()",) * 3)
        while any(len(run) <= len(steps[i]) for i, run in got.items()):
            obs, reward, terminated, truncated, info = envs.recv()
            ids = list(info["env_id"])
            assert 1 <= len(ids) <= 2 and reward.shape == (len(ids),) and len(obs["instruction"]) == len(ids)
            for k, i in enumerate(ids):
                got[i].append((_row(obs, k), reward[k], terminated[k], truncated[k], _row(info, k)))
            todo = [i for i in ids if len(got[i]) <= len(steps[i])]
            if todo:
                envs.send(tuple(steps[i][len(got[i]) - 1] for i in todo), env_ids=todo)
        with pytest.raises(ValueError, match="1 actions for 2 env ids"):
            envs.send(("finish()",), env_ids=[0, 1])
    finally:
        envs.close()
    for i in range(3):
        one = gym.make_vec(ENV_ID, num_envs=1, vectorization_mode="sync", max_episode_steps=3, **SMALL)
        try:
            obs, info = one.reset(seed=7 + i)
            want = [(_row(obs, 0), np.float64(0.0), np.False_, np.False_, {**_row(info, 0), "env_id": np.int64(i)})]
            for action in steps[i]:
                obs, reward, terminated, truncated, info = one.step((action,))
                want.append((_row(obs, 0), reward[0], terminated[0], truncated[0],
                             {**_row(info, 0), "env_id": np.int64(i)}))
        finally:
            one.close()
        assert any(w[2] or w[3] for w in want[1:-1]), "an autoreset happened"
        for t, (a, b) in enumerate(zip(got[i], want, strict=True)):
            assert data_equivalence(a, b), f"env {i} step {t}: {a} != {b}"


def test_a_workers_error_names_it_with_its_traceback():
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", strict=True, **SMALL)
    pids, names = worker_pids(envs), _ours(envs)
    try:
        envs.reset(seed=0)
        with pytest.raises(WorkerError, match=r"worker 1 \(pid \d+\) of Legent/ComeHere-OneRoom-v0 raised "
                                              r"ActionParseError in step") as raised:
            envs.step(("rotate_right(10)", "fly()"))
        assert raised.value.index == 1 and "The worker's traceback:\nTraceback" in str(raised.value)
        with pytest.raises(RuntimeError, match="cannot go on after a worker's error"):
            envs.step(("rotate_right(10)", "rotate_right(10)"))
    finally:
        envs.close()
    _assert_gone(pids)
    del raised  # its traceback's frames hold the semaphores, whose names go when they are freed
    gc.collect()
    _assert_shm_gone(names)


def test_a_killed_worker_is_named_and_close_cleans_up():
    envs = gym.make_vec(ENV_ID, num_envs=3, vectorization_mode="vector_entry_point", **SMALL)
    pids, names = worker_pids(envs), _ours(envs)
    try:
        envs.reset(seed=0)
        os.kill(pids[1], signal.SIGKILL)
        with pytest.raises(WorkerError, match=r"worker 1 \(pid \d+\) of .* died while step \(exit code -9\)"):
            envs.step(("rotate_right(10)",) * 3)
    finally:
        envs.close()
    _assert_gone(pids)
    _assert_shm_gone(names)


def test_unsupported_observation_spaces_are_refused_by_name():
    with pytest.raises(TypeError, match="Graph spaces.*vectorization_mode='async'"):
        _leaves(gym.spaces.Dict({"g": gym.spaces.Graph(gym.spaces.Box(0, 1, (2,)), None)}))


_ORPHAN = """
import os, sys
sys.path.insert(0, {repo!r})
import gymnasium as gym
import legent_gym
from legent_gym.envs.shared_vector import worker_pids
from tests.envs.test_vector_entry_point import _ours

if __name__ == "__main__":
    envs = gym.make_vec({env_id!r}, num_envs=2, vectorization_mode="vector_entry_point", width=32, height=32)
    envs.reset(seed=0)
    print(*worker_pids(envs), flush=True)
    print(*_ours(envs), flush=True)
    os.kill(os.getpid(), 9)  # no close, no atexit
"""


def test_workers_end_when_their_process_is_killed(tmp_path):
    """Killed with -9 (no close, no atexit): the workers see it and end; the semaphores'
    names go with multiprocessing's resource tracker."""
    script = tmp_path / "orphan.py"
    script.write_text(textwrap.dedent(_ORPHAN.format(repo=str(Path(__file__).resolve().parents[2]), env_id=ENV_ID)))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=240)
    lines = done.stdout.splitlines()
    assert done.returncode == -9 and len(lines) == 2, done.stderr[-2000:]
    pids, names = [int(p) for p in lines[0].split()], lines[1].split()
    assert len(pids) == 2 and len(names) == 4
    _assert_gone(pids, seconds=30)
    _assert_shm_gone(names, seconds=30)


def _assert_gone(pids: list[int], seconds: float = 10.0) -> None:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        alive = [p for p in pids if psutil.pid_exists(p) and psutil.Process(p).status() != psutil.STATUS_ZOMBIE]
        if not alive:
            return
        time.sleep(0.1)
    pytest.fail(f"worker processes still running: {alive}")
