"""The trained VLA as a policy: ``reset(instruction)``, then ``act(obs) -> action code``.

It keeps the last k views and the actions it wrote between them: the same window the
training lines hold. Decoding is greedy, so the policy itself is deterministic.
"""

from __future__ import annotations

import os
from collections import deque
from typing import Any

import numpy as np
import torch

from baselines.vla.checkpoint import load_model
from baselines.vla.dataset import window_inputs


class VLAPolicy:
    def __init__(self, checkpoint: str | os.PathLike):
        self.model, self.vocab = load_model(checkpoint)
        self.window = self.model.config.window
        self.image_size = self.model.config.image_size
        self._instruction = ""
        self._views: deque[np.ndarray] = deque(maxlen=self.window)
        self._actions: deque[str] = deque(maxlen=self.window - 1 if self.window > 1 else 1)

    @property
    def env_kwargs(self) -> dict[str, int]:
        """The view size the model was trained on (make the env with these)."""
        return {"width": self.image_size, "height": self.image_size}

    def reset(self, instruction: str) -> None:
        self._instruction = instruction
        self._views.clear()
        self._actions.clear()

    @torch.no_grad()
    def act(self, observation: dict[str, Any]) -> str:
        rgb = np.asarray(observation["rgb"])
        if rgb.shape != (self.image_size, self.image_size, 3):
            raise ValueError(f"the view is {rgb.shape[1]}x{rgb.shape[0]} but the model was trained on "
                             f"{self.image_size}x{self.image_size}: make the env with "
                             f"width={self.image_size}, height={self.image_size}")
        self._views.append(rgb)
        history = list(self._actions)[-(len(self._views) - 1):] if len(self._views) > 1 else []
        inputs = window_inputs(self.model.codec, self.vocab, self.window, self._instruction, history)
        n = len(self._views)
        shown = np.full((1, self.window), -1, np.int64)
        shown[0, self.window - n:] = np.arange(n)
        out = self.model(images=torch.from_numpy(np.stack(self._views)).permute(0, 3, 1, 2).contiguous(),
                         window_images=torch.from_numpy(shown),
                         **{k: torch.from_numpy(v[None]) for k, v in inputs.items()})
        action = self.model.decode(out)[0]
        self._actions.append(action)
        return action


def partner(checkpoint: str) -> VLAPolicy:
    """The model at ``checkpoint`` as the agent's partner in ``legent-gym play``:
    ``--partner baselines.vla.policy:partner:CHECKPOINT`` (run from the repository root with
    the baselines extra; the env's view is made at the size the model was trained on)."""
    if not os.path.isfile(checkpoint):
        raise ValueError(f"no checkpoint file {checkpoint!r}")
    return VLAPolicy(checkpoint)
