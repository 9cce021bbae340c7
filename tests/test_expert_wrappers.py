"""Expert wrappers: labels in the env's own action space, demonstrations, and DAgger."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import legent_gym  # noqa: F401
from legent_gym.agent.actions import MoveForward, RotateDown, RotateRight, format_actions
from legent_gym.envs.action_spaces import actions_to_dict
from legent_gym.wrappers import ExpertInfo, ExpertPolicy


@pytest.mark.parametrize("action_type", ["text", "continuous"])
def test_expert_action_is_in_the_envs_action_space(action_type):
    env = ExpertInfo(gym.make("Legent/PickUp-OneRoom-v0", width=32, height=32, action_type=action_type))
    _, info = env.reset(seed=3)
    assert env.action_space.contains(info["expert_action"])
    assert info["expert_problem"] == ""
    for _ in range(25):
        action = info["expert_action"]
        assert env.action_space.contains(action)
        _, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    assert info["success"]
    env.close()


def test_expert_policy_collects_a_demonstration():
    env = ExpertPolicy(gym.make("Legent/ComeHere-TwoRoom-v0", width=32, height=32))
    _, info = env.reset(seed=4)
    taken = []
    while True:
        planned = info["expert_action"]
        _, reward, terminated, truncated, info = env.step(None)
        assert info["action_taken"] == planned
        taken.append(planned)
        if terminated or truncated:
            break
    assert info["success"] and reward == 1.0
    assert 1 <= len(taken) <= 25
    env.close()


def _random_step(rng: np.random.Generator) -> tuple:
    return (MoveForward(round(float(rng.uniform(0, 1.5)), 2)), RotateRight(round(float(rng.uniform(-90, 90)), 1)),
            RotateDown(round(float(rng.uniform(-20, 20)), 1)))


def dagger_success(env_id: str, seeds, k: int, action_type: str = "text") -> tuple[int, int]:
    """Episodes where the expert, taking over after ``k`` random actions, succeeds; and
    episodes where success was still possible (not yet ended by the random actions)."""
    env = ExpertInfo(gym.make(env_id, width=32, height=32, action_type=action_type, max_episode_steps=25 + k))
    rng = np.random.default_rng(0)
    wins = possible = 0
    for seed in seeds:
        _, info = env.reset(seed=seed)
        ended = False
        for _ in range(k):
            step = _random_step(rng)
            action = format_actions(step) if action_type == "text" else actions_to_dict(step)
            _, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                ended = True
                break
        if ended:
            continue
        possible += 1
        for _ in range(25):
            _, _, terminated, truncated, info = env.step(info["expert_action"])
            if terminated or truncated:
                break
        wins += bool(info["success"])
    env.close()
    return wins, possible


@pytest.mark.parametrize("env_id", ["Legent/ComeHere-TwoRoom-v0", "Legent/PickUp-OneRoom-v0"])
def test_dagger_expert_takes_over_after_random_actions(env_id):
    wins, possible = dagger_success(env_id, range(6), k=4)
    assert possible >= 3
    assert wins == possible


@pytest.mark.slow
@pytest.mark.parametrize("env_id", ["Legent/ComeHere-TwoRoom-v0", "Legent/BringMe-TwoRoom-v0",
                                    "Legent/PutOn-OneRoom-v0", "Legent/WhereIs-TwoRoom-v0"])
def test_dagger_acceptance(env_id):
    wins, possible = dagger_success(env_id, range(200), k=5)
    print(f"{env_id}: DAgger {wins}/{possible}")
    assert wins >= 0.99 * possible
