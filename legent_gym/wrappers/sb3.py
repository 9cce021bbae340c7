"""Wrappers that make the environments usable by stable-baselines3 and similar libraries.

SB3 cannot take ``Text`` spaces. :class:`InstructionTokens` turns every Text observation
into a fixed-length integer Box (a hashing word tokenizer: stable across processes, no
vocabulary file), and :class:`FlatActions` offers a flat ``Box(4)`` in [-1, 1] mapped onto
the env's actions: move forward, turn, tilt, and interact (when the fourth value > 0.5).

    env = for_sb3(gym.make("Legent/ComeHere-OneRoom-v0", reward="dense"))  # the two, in this order
    PPO("MultiInputPolicy", env).learn(10_000)

``stable_baselines3.common.env_checker.check_env`` passes on :func:`for_sb3`'s stack (not on
the raw env, whose ``Text`` observations are no arrays, nor on ``InstructionTokens`` alone
with text actions). The PettingZoo envs have the same stack in
:func:`legent_gym.multiagent.for_sb3`.
"""

from __future__ import annotations

import re
import zlib

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from legent_gym.agent.actions import ActionLimits, format_number

_WORD = re.compile(r"[a-z0-9']+")


def tokenize(text: str, vocab_size: int, max_tokens: int) -> np.ndarray:
    """Word ids in [1, vocab_size) (0 pads), by a stable hash of each lower-cased word."""
    ids = [1 + zlib.crc32(w.encode()) % (vocab_size - 1) for w in _WORD.findall(text.lower())][:max_tokens]
    out = np.zeros(max_tokens, dtype=np.int64)
    out[: len(ids)] = ids
    return out


class InstructionTokens(gym.ObservationWrapper, gym.utils.RecordConstructorArgs):
    """Every Text observation becomes a Box of ``max_tokens`` word ids (0 = padding)."""

    def __init__(self, env: gym.Env, vocab_size: int = 1024, max_tokens: int = 16):
        gym.utils.RecordConstructorArgs.__init__(self, vocab_size=vocab_size, max_tokens=max_tokens)
        gym.ObservationWrapper.__init__(self, env)
        self.vocab_size, self.max_tokens = vocab_size, max_tokens
        source = env.observation_space
        if not isinstance(source, spaces.Dict):
            raise TypeError(f"InstructionTokens needs a Dict observation space, got {source}")
        self.source_space: spaces.Dict = source
        self.observation_space = token_space(source, vocab_size, max_tokens)

    def observation(self, observation):
        return tokenize_texts(observation, self.source_space, self.vocab_size, self.max_tokens)


def token_space(source: spaces.Dict, vocab_size: int, max_tokens: int) -> spaces.Dict:
    """``source`` with every ``Text`` entry as a Box of ``max_tokens`` word ids (what
    :class:`InstructionTokens` observes)."""
    return spaces.Dict({key: spaces.Box(0, vocab_size - 1, (max_tokens,), np.int64)
                        if isinstance(space, spaces.Text) else space for key, space in source.spaces.items()})


def tokenize_texts(observation: dict, source: spaces.Dict, vocab_size: int, max_tokens: int) -> dict:
    """A copy of ``observation`` with the entries ``source`` holds as ``Text`` tokenized."""
    out = dict(observation)
    for key, space in source.spaces.items():
        if isinstance(space, spaces.Text):
            out[key] = tokenize(observation[key], vocab_size, max_tokens)
    return out


class FlatActions(gym.ActionWrapper, gym.utils.RecordConstructorArgs):
    """A ``Box(-1, 1, (4,))`` action: [move, turn right, tilt down, interact].

    move -1..1 maps to 0..max metres; turn and tilt to +-max degrees; interact happens when
    the fourth value exceeds 0.5. Works over text and continuous action types.
    """

    def __init__(self, env: gym.Env):
        gym.utils.RecordConstructorArgs.__init__(self)
        gym.ActionWrapper.__init__(self, env)
        self.action_space = spaces.Box(-1.0, 1.0, (4,), np.float32)
        episode = getattr(env.unwrapped, "episode", None)  # HouseholdEnv's, SingleAgentEnv's
        if episode is None:
            raise TypeError(f"FlatActions needs a legent_gym env (one with an episode engine), got {env.unwrapped}")
        self.limits: ActionLimits = episode.limits

    def action(self, action):
        return flat_action_text(action, self.limits)


def flat_action_text(action, limits: ActionLimits) -> str:
    """The action code of a flat ``[move, turn right, tilt down, interact]`` action in [-1, 1]
    (what :class:`FlatActions` sends; also for policies that act outside the wrapper)."""
    a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
    move = (a[0] + 1.0) / 2.0 * limits.max_move
    turn = a[1] * limits.max_rotate_right
    tilt = a[2] * limits.max_rotate_down
    parts = [f"move_forward({format_number(round(move, 3))})", f"rotate_right({format_number(round(turn, 2))})",
             f"rotate_down({format_number(round(tilt, 2))})"]
    if a[3] > 0.5:
        parts.append("interact()")
    return ", ".join(parts)


def for_sb3(env: gym.Env, vocab_size: int = 1024, max_tokens: int = 16) -> FlatActions:
    """The stack stable-baselines3 takes: ``FlatActions(InstructionTokens(env))``.

    Observations: a Dict of Boxes (``rgb`` and the images as they are, ``instruction`` and
    ``message`` as word ids), for ``"MultiInputPolicy"``; actions: a ``Box(-1, 1, (4,))``.
    SB3's ``check_env`` passes on it; RL Baselines3 Zoo names it as ``env_wrapper``
    (``legent_gym/hyperparams/ppo.yml``)."""
    return FlatActions(InstructionTokens(env, vocab_size, max_tokens))
