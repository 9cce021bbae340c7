"""A fine-tuned VLM as a policy: ``reset(instruction)``, ``act(obs) -> action code``.

The prompt is the training sample's (:mod:`baselines.vlm.data`): the instruction, the last
``window`` views and the actions between them, in the model's chat template. Decoding is
greedy, so the policy is deterministic; :meth:`VLMPolicy.act_batch` decodes several
episodes' steps in one ``generate`` call (left-padded), and :func:`run_episodes` runs a
chunk of episodes in lockstep on it. Replies go through the LLM agent's parser
(:func:`baselines.llm_agent.extract_action`); a reply with no valid action code becomes
:data:`baselines.llm_agent.NOOP_ACTION` (``rotate_right(0)``: a valid step that changes
nothing) and the reason is kept in ``policy.fallbacks``. Unlike the LLM agent it does not
ask again with the parse error: the model was trained on the training prompt alone, and
greedy decoding of that prompt gives the same reply every time.

``baselines/evaluate.py --policy vlm:PATH`` and ``reproduce_table.py --model vlm:PATH``
evaluate through :func:`run_chunk`.
"""

from __future__ import annotations

import os
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import gymnasium as gym
import numpy as np
from PIL import Image

from baselines.episodes import EpisodeResult
from baselines.llm_agent import NOOP_ACTION, extract_action
from baselines.vlm.data import Encoder
from baselines.vlm.model import check_source, load_model, load_processor, pick_dtype, read_meta
from legent_gym.agent.actions import ActionParseError

PREFIX = "vlm:"


@dataclass
class _Episode:
    instruction: str = ""
    views: deque = field(default_factory=deque)
    actions: deque = field(default_factory=deque)


class VLMPolicy:
    """Args:
        source: a model folder (``OUT/final`` of :mod:`baselines.vlm.train`) or hub id.
        window: views per prompt (default: what the model was trained on, else 6).
        device: ``auto`` (the GPU when there is one), ``cpu``, ``cuda``, ``cuda:1``, ...
        max_new_tokens: the longest reply decoded.
    """

    def __init__(self, source: str | os.PathLike, window: int | None = None, device: str = "auto",
                 max_new_tokens: int = 48, dtype: str = "auto"):
        # the vlm extra's libraries take seconds to import: only when a model is made or run
        import torch

        self.source = check_source(source)
        self.meta = read_meta(self.source)
        self.window = window or int(self.meta.get("window", 6))
        if self.window < 1:
            raise ValueError(f"window must be >= 1 view, got {self.window}")
        if device == "auto":
            device = "cuda" if torch.cuda.is_available() else "cpu"
        self.device = device
        self.processor = load_processor(self.source)
        self.encoder = Encoder(self.processor)
        self.model = load_model(self.source, pick_dtype(device, dtype)).to(device).eval()
        self.max_new_tokens = max_new_tokens
        self.fallbacks: list[str] = []  # why a step fell back to NOOP_ACTION, one entry per such step
        self.replies = 0
        self._single = _Episode()

    @property
    def env_kwargs(self) -> dict[str, int]:
        """The view size the model was trained on (empty when it was not trained here)."""
        if "width" in self.meta:
            return {"width": int(self.meta["width"]), "height": int(self.meta["height"])}
        return {}

    def new_episode(self, instruction: str) -> _Episode:
        return _Episode(instruction, deque(maxlen=self.window), deque(maxlen=max(self.window - 1, 1)))

    def reset(self, instruction: str) -> None:
        self._single = self.new_episode(instruction)

    def act(self, observation: dict[str, Any]) -> str:
        return self.act_batch([self._single], [observation])[0]

    def act_batch(self, episodes: Sequence[_Episode], observations: Sequence[dict[str, Any]]) -> list[str]:
        """The next action of each episode (from :meth:`new_episode`), decoded in one batch."""
        # the vlm extra's libraries take seconds to import: only when a model is made or run
        import torch
        prompts, images = [], []
        for episode, obs in zip(episodes, observations, strict=True):
            episode.views.append(Image.fromarray(np.ascontiguousarray(obs["rgb"], dtype=np.uint8)))
            history = list(episode.actions)[len(episode.actions) - (len(episode.views) - 1):] \
                if len(episode.views) > 1 else []
            prompts.append(self.encoder.prompt(episode.instruction, len(episode.views), history))
            images.append(list(episode.views))
        tokenizer = self.encoder.tokenizer
        tokenizer.padding_side = "left"
        batch = self.processor(text=prompts, images=images, padding=True, return_tensors="pt")
        dtype = self.model.dtype  # pixel values in the weights' dtype (bfloat16 on a GPU)
        inputs = {k: v.to(self.device, dtype=dtype) if v.is_floating_point() else v.to(self.device)
                  for k, v in batch.items()}
        with torch.no_grad():
            out = self.model.generate(**inputs, max_new_tokens=self.max_new_tokens, do_sample=False,
                                      pad_token_id=tokenizer.pad_token_id)
        replies = tokenizer.batch_decode(out[:, inputs["input_ids"].shape[1]:], skip_special_tokens=True)
        actions = []
        for episode, reply in zip(episodes, replies):
            self.replies += 1
            try:
                action = extract_action(reply)
            except ActionParseError as err:
                self.fallbacks.append(f"no valid action code in {reply!r} ({err})")
                action = NOOP_ACTION
            episode.actions.append(action)
            actions.append(action)
        return actions


def run_episodes(policy: VLMPolicy, env_id: str, episodes: int, seed: int, env_kwargs: dict | None = None,
                 batch: int = 10) -> list[EpisodeResult]:
    """Episodes ``seed .. seed + episodes - 1`` as :func:`baselines.evaluate.run_episodes`
    runs them (the same resets, the same results), ``batch`` at a time in lockstep, each
    step's actions decoded together."""
    results: list[EpisodeResult] = []
    for start in range(0, episodes, batch):
        count = min(batch, episodes - start)
        envs = [gym.make(env_id, **(env_kwargs or {})) for _ in range(count)]
        try:
            obs, states, totals, steps = [], [], [0.0] * count, [0] * count
            for k, env in enumerate(envs):
                o, _ = env.reset(seed=seed + start + k)
                obs.append(o)
                states.append(policy.new_episode(o["instruction"]))
            done: dict[int, EpisodeResult] = {}
            while len(done) < count:
                live = [k for k in range(count) if k not in done]
                actions = policy.act_batch([states[k] for k in live], [obs[k] for k in live])
                for k, action in zip(live, actions):
                    o, reward, terminated, truncated, info = envs[k].step(action)
                    obs[k] = o
                    totals[k] += float(reward)
                    steps[k] += 1
                    if terminated or truncated:
                        done[k] = EpisodeResult(seed + start + k, o["instruction"], bool(info["success"]), steps[k],
                                                totals[k], info.get("house_seed"), info.get("distance_to_goal"))
            results += [done[k] for k in range(count)]
        finally:
            for env in envs:
                env.close()
    return results


_policies: dict[str, VLMPolicy] = {}


def check_spec(spec: str) -> str:
    """``vlm:PATH`` with PATH checked (:class:`~baselines.vlm.model.ModelError` names what is wrong)."""
    if not spec.startswith(PREFIX):
        raise ValueError(f"a VLM policy is vlm:PATH, got {spec!r}")
    return PREFIX + check_source(spec[len(PREFIX):])


def view_size(spec: str) -> dict[str, int]:
    """The ``width``/``height`` a ``vlm:PATH`` model was trained on (empty if unknown)."""
    meta = read_meta(check_source(spec[len(PREFIX):]))
    return {"width": int(meta["width"]), "height": int(meta["height"])} if "width" in meta else {}


def run_chunk(spec: str, env_id: str, seed: int, episodes: int, env_kwargs: dict) -> list[EpisodeResult]:
    """One evaluation chunk of a ``vlm:PATH`` spec (the model is loaded once per process)."""
    if spec not in _policies:
        _policies[spec] = VLMPolicy(spec[len(PREFIX):])
    return run_episodes(_policies[spec], env_id, episodes, seed, env_kwargs)
