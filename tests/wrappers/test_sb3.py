"""stable-baselines3 runs on the environments through the wrappers."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from legent_gym.wrappers import FlatActions, InstructionTokens, tokenize

sb3 = pytest.importorskip("stable_baselines3", reason="install the 'rl' extra: pip install -e '.[rl]'")


def _env(**kwargs):
    return FlatActions(InstructionTokens(gym.make("Legent/ComeHere-OneRoom-v0", width=48, height=48,
                                                  reward="dense", **kwargs)))


def test_tokenize_is_stable_and_padded():
    a = tokenize("Come here, please.", 1024, 8)
    assert a.shape == (8,) and (a[3:] == 0).all() and (a[:3] > 0).all()
    assert (a == tokenize("come HERE please", 1024, 8)).all()


@pytest.mark.parametrize("action_type", ["text", "continuous"])
def test_sb3_check_env(action_type):
    from stable_baselines3.common.env_checker import check_env

    check_env(_env(action_type=action_type), warn=True)


def test_flat_action_maps_to_action_code():
    env = _env()
    assert env.action(np.array([1, -1, 0, 0.9])) == "move_forward(2), rotate_right(-90), rotate_down(0), interact()"


def test_short_ppo_run():
    from stable_baselines3 import PPO

    from legent_gym.agent.actions import parse_actions

    env = _env()
    model = PPO("MultiInputPolicy", env, n_steps=32, batch_size=16, n_epochs=1, seed=0, device="cpu")
    before = {k: v.clone() for k, v in model.policy.state_dict().items()}
    model.learn(total_timesteps=64)
    assert model.num_timesteps == 64
    # The episodes PPO played (Monitor's records): the dense reward is -0.01 a step plus the
    # change of distance to the user, so the agent moved in them.
    episodes = list(model.ep_info_buffer)
    assert episodes and all(ep["l"] == 25 or ep["r"] > 9 for ep in episodes)  # time limit, or success (+10)
    assert any(abs(ep["r"] + 0.01 * ep["l"]) > 0.05 for ep in episodes)
    after = model.policy.state_dict()
    assert any(not (before[k] == after[k]).all() for k in before)  # the updates moved the weights
    action, _ = model.predict(_env().reset(seed=0)[0], deterministic=True)
    assert env.action_space.contains(action.astype(env.action_space.dtype))
    assert parse_actions(env.action(action))  # the learned policy's action is action code the env runs
