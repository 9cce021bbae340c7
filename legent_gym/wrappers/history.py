"""LEGENT-style image-text interleaved history (the paper's model input).

The paper's model reads ``Observation: <image> Action: <code>`` for the last few steps. This
wrapper adds that history to every observation:

* ``history_rgb``: Box (k, H, W, 3) uint8, the last k egocentric frames, oldest first,
  zero-padded at the start of an episode;
* ``history_text``: Text, the interleaved prompt with one ``<image>`` placeholder per frame
  in ``history_rgb`` (the real frames only), e.g.
  ``Observation: <image> Action: rotate_right(-45)\\nObservation: <image> Action:``.
"""

from __future__ import annotations

from collections import deque

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from legent_gym.envs.action_spaces import speech_space
from legent_gym.envs.text_space import VectorSafeText

IMAGE_TOKEN = "<image>"


class InterleavedHistory(gym.Wrapper, gym.utils.RecordConstructorArgs):
    def __init__(self, env: gym.Env, k: int = 6, max_text: int = 4000):
        gym.utils.RecordConstructorArgs.__init__(self, k=k, max_text=max_text)
        gym.Wrapper.__init__(self, env)
        if k < 1:
            raise ValueError(f"history length k must be >= 1, got {k}")
        self.k = k
        source = env.observation_space
        rgb = source.spaces.get("rgb") if isinstance(source, spaces.Dict) else None
        if not isinstance(source, spaces.Dict) or not isinstance(rgb, spaces.Box):
            raise TypeError(f"InterleavedHistory needs a Dict observation space with an 'rgb' Box, got {source}")
        #: (k, H, W, 3): the shape of ``history_rgb``.
        self._history_shape = (k, *rgb.shape)
        self.observation_space = spaces.Dict({
            **source.spaces,
            "history_rgb": spaces.Box(0, 255, self._history_shape, np.uint8),
            "history_text": VectorSafeText(max_length=max_text, min_length=0,
                                           charset=speech_space().character_set | set("<>\n")),
        })
        # (frame, the action taken from it); the newest frame has no action yet.
        self._steps: deque[list] = deque(maxlen=k)

    def _with_history(self, obs):
        stack = np.zeros(self._history_shape, dtype=np.uint8)
        stack[self.k - len(self._steps):] = np.stack([frame for frame, _ in self._steps])
        text = "\n".join(f"Observation: {IMAGE_TOKEN} Action:" + (f" {action}" if action else "")
                         for _, action in self._steps)
        return {**obs, "history_rgb": stack, "history_text": text}

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        self._steps.clear()
        self._steps.append([obs["rgb"], ""])
        return self._with_history(obs), info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        self._steps[-1][1] = info.get("action_text", str(action))
        self._steps.append([obs["rgb"], ""])
        return self._with_history(obs), reward, terminated, truncated, info
