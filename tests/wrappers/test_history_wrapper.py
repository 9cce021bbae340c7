"""The LEGENT-style interleaved history wrapper."""

from __future__ import annotations

import gymnasium as gym
import pytest

from legent_gym.wrappers import InterleavedHistory


def test_history_window_pairs_frames_with_their_actions():
    env = InterleavedHistory(gym.make("Legent/ComeHere-OneRoom-v0", width=32, height=32), k=3)
    obs, _ = env.reset(seed=0)
    assert obs["history_text"] == "Observation: <image> Action:"
    assert (obs["history_rgb"][:2] == 0).all() and (obs["history_rgb"][2] == obs["rgb"]).all()
    frames = [obs["rgb"]]
    for action in ["rotate_right(30)", "move_forward(1)", "rotate_right(-45)", "rotate_down(10)"]:
        obs, *_ = env.step(action)
        frames.append(obs["rgb"])
        assert env.observation_space.contains(obs)
    lines = obs["history_text"].splitlines()
    assert lines == ["Observation: <image> Action: rotate_right(-45)", "Observation: <image> Action: rotate_down(10)",
                     "Observation: <image> Action:"]
    assert all((obs["history_rgb"][i] == frames[-3 + i]).all() for i in range(3))


def test_history_length_must_be_positive():
    with pytest.raises(ValueError, match="k must be"):
        InterleavedHistory(gym.make("Legent/ComeHere-OneRoom-v0", width=32, height=32), k=0)
