"""Vector envs: each worker process pinned to a core of its own (legent_gym/envs/vector.py)."""

import os

import gymnasium as gym
import numpy as np
import pytest

import legent_gym  # noqa: F401
from legent_gym.envs.vector import settle_worker, worker_number


def test_the_main_process_is_left_alone():
    assert worker_number() is None
    assert settle_worker() is None


@pytest.mark.skipif(not hasattr(os, "sched_getaffinity") or len(os.sched_getaffinity(0)) < 2,
                    reason="needs two cores")
def test_async_workers_are_pinned_to_different_cores_and_still_step():
    envs = gym.make_vec("Legent/ComeHere-OneRoom-v0", num_envs=2, vectorization_mode="async",
                        vector_kwargs={"context": "forkserver"}, width=32, height=32, episodes_per_house=4)
    try:
        cores = envs.get_attr("worker_core")
        assert len(set(cores)) == 2 and set(cores) <= os.sched_getaffinity(0)
        obs, _ = envs.reset(seed=0)
        obs, *_ = envs.step(np.array(["move_forward(0.5)", "rotate_right(30)"], dtype=object))
        assert obs["rgb"].shape == (2, 32, 32, 3)
    finally:
        envs.close()
    unpinned = gym.make_vec("Legent/ComeHere-OneRoom-v0", num_envs=2, vectorization_mode="async",
                            vector_kwargs={"context": "forkserver"}, width=32, height=32, pin_worker=False)
    try:
        assert unpinned.get_attr("worker_core") == (None, None)
        assert [episode.prepare_ahead for episode in unpinned.get_attr("episode")] == [False, False]
    finally:
        unpinned.close()


@pytest.mark.skipif(not hasattr(os, "sched_getaffinity") or len(os.sched_getaffinity(0)) < 2,
                    reason="needs two cores")
def test_pinned_workers_make_their_next_house_ahead():
    envs = gym.make_vec("Legent/ComeHere-OneRoom-v0", num_envs=2, vectorization_mode="async",
                        vector_kwargs={"context": "forkserver"}, width=32, height=32)
    try:
        envs.reset(seed=0)
        assert [episode.prepare_ahead for episode in envs.get_attr("episode")] == [True, True]
        for _ in range(60):  # at least two episodes each (25 actions at most)
            envs.step(np.array(["rotate_right(30)", "rotate_right(30)"], dtype=object))
        assert all(episode.houses_taken_ahead >= 1 for episode in envs.get_attr("episode"))
    finally:
        envs.close()
