"""Episode helpers (legent_gym/envs/factory.py): the same episodes, taken ready-made, and
helper processes that end with their env."""

from __future__ import annotations

import os
import pickle
import signal
import subprocess
import sys
import time

import gymnasium as gym
import numpy as np
import psutil
import pytest

import legent_gym  # noqa: F401
from legent_gym.envs.factory import HelperDied, HouseAssets
from legent_gym.world.generation import generate_house
from legent_gym.world.scene import save_scene

SIZE = 32
ACTIONS = ("rotate_right(75)", "move_forward(1.2)", "grab()", "rotate_down(20)", "open()", "rotate_right(-40)",
           "move_forward(0.6), put()", "interact()")
INFO_KEYS = ("agent_pose", "user_pose", "held", "task", "success", "distance_to_goal", "house_seed", "scene_name",
             "n_actions", "action_results")


def _record(env, obs, info, out: list) -> None:
    out.append({k: np.asarray(v).tobytes() if isinstance(v, np.ndarray) else v for k, v in obs.items()})
    out.append({k: info.get(k) for k in INFO_KEYS})


def _run(env_id: str, *, seeds, unseeded: int, between=None, **kwargs):
    """Observations and infos of seeded resets, each followed by ``unseeded`` episodes (8
    steps each, then an unseeded reset, as autoreset does)."""
    env = gym.make(env_id, width=SIZE, height=SIZE, depth=True, segmentation=True, **kwargs)
    out: list = []
    try:
        for seed in seeds:
            obs, info = env.reset(seed=seed)
            _record(env, obs, info, out)
            for episode in range(unseeded):
                for i in range(8):
                    obs, reward, terminated, truncated, info = env.step(ACTIONS[(i + episode) % len(ACTIONS)])
                    _record(env, obs, info, out)
                    out.append((reward, terminated, truncated))
                    if terminated:
                        break
                if between is not None:
                    between(env)
                obs, info = env.reset()
                _record(env, obs, info, out)
        return out, env.unwrapped.episode.episodes_from_helpers
    finally:
        env.close()


def _assert_same(a: list, b: list) -> None:
    assert len(a) == len(b)
    for i, (x, y) in enumerate(zip(a, b)):
        assert x == y, f"entry {i} differs"


def _stage_all(env) -> None:
    """Have the next episode staged completely (as many steps' stage() as it takes)."""
    episode = env.unwrapped.episode
    deadline = time.monotonic() + 120
    while not episode.staged:
        assert time.monotonic() < deadline, "the next episode was never staged"
        episode.stage()
        time.sleep(0.002)


@pytest.mark.parametrize(("env_id", "episodes_per_house"), [("Legent/PickUp-OneRoom-v0", 1),
                                                             ("Legent/ComeHere-TwoRoom-v0", 3)])
def test_a_staged_episode_is_the_same_episode(env_id, episodes_per_house):
    # Every unseeded reset finds its episode staged: house loaded, bodies placed, meshes
    # uploaded and the first frame drawn ahead, in the pieces stage() does after steps.
    kwargs = {"seeds": (7, 3), "unseeded": 3, "episodes_per_house": episodes_per_house}
    inline, _ = _run(env_id, **kwargs)
    envs: list = []

    def between(env):
        envs[:] = [env]
        _stage_all(env)

    helped, taken = _run(env_id, helpers=1, between=between, **kwargs)
    _assert_same(inline, helped)
    staged = envs[0].unwrapped.episode.episodes_staged
    # every unseeded reset into a new house (all six with one episode per house; with three,
    # seed 7's block ends after seed 8 and seed 3's after seed 5)
    assert taken == 6 and staged == (6 if episodes_per_house == 1 else 2), (taken, staged)


@pytest.mark.parametrize(("env_id", "episodes_per_house"), [("Legent/PickUp-OneRoom-v0", 1),
                                                             ("Legent/ComeHere-TwoRoom-v0", 3)])
def test_helpers_give_the_same_episodes(env_id, episodes_per_house):
    # Seed 7, its unseeded successors, then seed 3 (a seed nobody predicted) and its own.
    kwargs = {"seeds": (7, 3), "unseeded": 3, "episodes_per_house": episodes_per_house}
    inline, none = _run(env_id, **kwargs)
    helped, taken = _run(env_id, helpers=2, **kwargs)
    assert none == 0 and taken >= 4  # most unseeded resets took an episode a helper made
    _assert_same(inline, helped)


def test_helpers_give_the_same_episodes_from_a_houses_folder(tmp_path):
    for seed in (1, 2, 3):
        save_scene(generate_house(seed, "OneRoom"), tmp_path / f"OneRoom_{seed:06d}.json")
    kwargs = {"seeds": (4,), "unseeded": 5, "houses": str(tmp_path), "houses_kept": 2}
    inline, _ = _run("Legent/GoTo-OneRoom-v0", **kwargs)
    helped, taken = _run("Legent/GoTo-OneRoom-v0", helpers=1, **kwargs)
    assert taken >= 3
    _assert_same(inline, helped)


def _asset_facts(world) -> dict:
    return {i: (m.asset_id, m.category, m.names, m.bounds().tolist(), [(r.name, r.center, r.height) for r in m.receptacles],
                m.triangle_count()) for i, m in world.assets.items()}


def test_a_house_from_a_helper_has_the_same_asset_models():
    # Its library models come pickled one by one and are loaded on first use (HouseAssets).
    facts = []
    for helpers in (0, 1):
        env = gym.make("Legent/PutOn-TwoRoom-v0", width=SIZE, height=SIZE, helpers=helpers)
        try:
            env.reset(seed=6)
            env.reset()
            world = env.unwrapped.episode.world
            assert isinstance(world.assets, HouseAssets) == bool(helpers)
            assert env.unwrapped.episode.episodes_from_helpers == helpers
            facts.append(_asset_facts(world))
        finally:
            env.close()
    assert facts[0] == facts[1] and len(facts[0]) > 10


def test_a_house_comes_once_however_many_jobs_ask_for_its_episodes():
    # With 4 episodes per house and 8 ahead, a block's episodes are asked for over several
    # resets: only the first of them brings the house.
    env = gym.make("Legent/ComeHere-OneRoom-v0", width=SIZE, height=SIZE, helpers=1, episodes_per_house=4)
    try:
        env.reset(seed=1)  # played here: its house is known to the helper's later jobs
        episode = env.unwrapped.episode
        first = episode.house.draw.key
        keys = set()
        for _ in range(13):
            env.reset()
            keys.add(episode.house.draw.key)
        assert episode.episodes_from_helpers == 13
        assert episode._factory.houses_received == len(keys - {first}) == 3
    finally:
        env.close()


def test_a_moved_generator_is_followed_not_the_prepared_episodes():
    # Drawing from the env's generator between episodes changes the next block's seed (five
    # draws: beyond the seeds handed to the helper): what the helper made for the old ones
    # is not used, and the episodes stay those of a run without helpers.
    kwargs = {"seeds": (2,), "unseeded": 3,
              "between": lambda env: env.unwrapped.np_random.integers(2**31 - 1, size=5)}
    inline, _ = _run("Legent/ComeHere-OneRoom-v0", **kwargs)
    helped, taken = _run("Legent/ComeHere-OneRoom-v0", helpers=1, **kwargs)
    assert taken == 0
    _assert_same(inline, helped)


def test_an_unseeded_episode_is_the_episode_of_its_seed():
    env = gym.make("Legent/ComeHere-OneRoom-v0", width=SIZE, height=SIZE, episodes_per_house=2)
    env.reset(seed=5)
    seeds, infos = [], []
    for _ in range(3):
        obs, info = env.reset()
        seeds.append(env.unwrapped.episode.episode_seed)
        infos.append((obs["rgb"].tobytes(), info["agent_pose"], info["house_seed"]))
    # Seed 5 ends its block of two: then a block drawn from the generator, in one house.
    assert seeds[0] % 2 == 0 and seeds[1] == seeds[0] + 1 and seeds[2] % 2 == 0
    assert infos[0][2] == infos[1][2]
    fresh = gym.make("Legent/ComeHere-OneRoom-v0", width=SIZE, height=SIZE, episodes_per_house=2)
    obs, info = fresh.reset(seed=seeds[1])
    assert (obs["rgb"].tobytes(), info["agent_pose"], info["house_seed"]) == infos[1]
    env.close()
    fresh.close()


def _children(pids):
    return [p for p in pids if psutil.pid_exists(p) and psutil.Process(p).status() != psutil.STATUS_ZOMBIE]


def test_helpers_end_with_close_and_leave_nothing_behind():
    env = gym.make("Legent/ComeHere-OneRoom-v0", width=SIZE, height=SIZE, helpers=2)
    env.reset(seed=0)
    factory = env.unwrapped.episode._factory
    pids, folder = factory.pids, factory.folder
    assert len(pids) == 2 and all(psutil.pid_exists(p) for p in pids) and os.path.isdir(folder)
    env.step("move_forward(1)")
    env.reset()
    copy = pickle.loads(pickle.dumps(env.unwrapped.episode))  # a copy starts its own on use
    assert copy._factory is None and copy.helpers == 2
    env.close()
    assert _children(pids) == [] and not os.path.exists(folder)


def test_a_dead_helper_is_named_when_a_reset_waits_for_it():
    env = gym.make("Legent/ComeHere-TwoRoom-v0", width=SIZE, height=SIZE, helpers=1)
    try:
        env.reset(seed=0)
        (pid,) = env.unwrapped.episode._factory.pids
        os.kill(pid, signal.SIGKILL)
        deadline = time.monotonic() + 10
        while psutil.pid_exists(pid) and psutil.Process(pid).status() != psutil.STATUS_ZOMBIE:
            assert time.monotonic() < deadline
            time.sleep(0.05)
        with pytest.raises(HelperDied, match=f"pid {pid}.*status -9"):
            env.reset()
    finally:
        env.close()


def test_helpers_must_be_a_count():
    with pytest.raises(ValueError, match="helpers must be a non-negative integer"):
        gym.make("Legent/ComeHere-OneRoom-v0", helpers=-1)


_SCRIPT = """
import sys, time, gymnasium as gym, legent_gym
env = gym.make("Legent/ComeHere-OneRoom-v0", width=32, height=32, helpers=2)
env.reset(seed=0)
print(env.unwrapped.episode._factory.folder, *env.unwrapped.episode._factory.pids, flush=True)
if sys.argv[1] == "hang":
    time.sleep(600)
"""


def _gone(pids, seconds: float = 30.0) -> bool:
    deadline = time.monotonic() + seconds
    while _children(pids):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.1)
    return True


@pytest.mark.slow
@pytest.mark.parametrize("how", ["exit", "killed"])
def test_no_helper_outlives_its_env_process(how):
    # An env left open at interpreter exit, or whose process is killed: its helpers go too.
    proc = subprocess.Popen([sys.executable, "-c", _SCRIPT, "exit" if how == "exit" else "hang"],
                            stdout=subprocess.PIPE, text=True)
    try:
        folder, *pids = proc.stdout.readline().split()
        assert len(pids) == 2 and os.path.isdir(folder)
        if how == "killed":
            proc.kill()
        proc.wait(timeout=120)
        assert _gone([int(p) for p in pids]) and not os.path.exists(folder)
    finally:
        proc.kill()
        proc.wait()
