"""Policies and the seeded episode loop every baseline is evaluated in.

A policy is any object with ``reset(instruction)`` (a new episode begins) and
``act(observation) -> str`` (the next step as action code, e.g. ``"move_forward(1.5)"``);
see :class:`Policy`. Episode ``i`` resets the environment with seed ``seed + i``, so the
houses, goals and instructions depend on the seed only, and a policy whose own randomness
is seeded (through an optional ``seed(seed)`` method, called once before the first
episode) gives the same result every run. Success is the environment's own rule
(``info["success"]`` when the episode ends), under its step cap (25 actions, the paper's).
:mod:`baselines.evaluate` re-exports these names and is the command line.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import gymnasium as gym
import numpy as np

import legent_gym  # noqa: F401  (registers the environments)
from legent_gym.agent.actions import (
    ActionLimits,
    MoveForward,
    RotateDown,
    RotateRight,
    format_actions,
)
from legent_gym.envs.action_spaces import actions_to_dict
from legent_gym.experts import Expert
from legent_gym.wrappers import ExpertInfo
from legent_gym.wrappers.sb3 import flat_action_text


@runtime_checkable
class Policy(Protocol):
    """What :func:`evaluate` drives: told the instruction, then asked for one step at a time."""

    def reset(self, instruction: str) -> None: ...

    def act(self, observation: dict[str, Any]) -> str: ...


@dataclass(frozen=True)
class EpisodeResult:
    """One evaluated episode."""

    seed: int
    instruction: str
    success: bool
    steps: int
    episode_return: float
    house_seed: int | None
    final_distance: float | None  # the task's distance to its goal at the end (metres)


class RandomPolicy:
    """Uniformly random flat actions, the same distribution as a random agent in
    :class:`~legent_gym.wrappers.FlatActions`: move 0..2 m, turn and tilt +-90 degrees, and
    ``interact()`` a quarter of the time. The baseline every learned policy must beat."""

    def __init__(self, seed: int = 0, limits: ActionLimits | None = None):
        self.limits = limits or ActionLimits()
        self.seed(seed)

    def seed(self, seed: int) -> None:
        self._rng = np.random.default_rng(seed)

    def reset(self, instruction: str) -> None:
        pass  # it ignores the instruction, by definition

    def act(self, observation: dict[str, Any]) -> str:
        return flat_action_text(self._rng.uniform(-1.0, 1.0, 4), self.limits)


class ExpertBaseline:
    """The task expert as a :class:`Policy`: the upper bound of every table. It plans from
    privileged state, so :func:`run_episodes` hands it the env first (``bind``)."""

    def __init__(self):
        self._expert = None

    def bind(self, env) -> None:
        self._expert = Expert(env)

    def reset(self, instruction: str) -> None:
        pass

    def act(self, observation: dict[str, Any]) -> str:
        return self._expert.action()


def check_counts(episodes: int, seed: int) -> None:
    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise ValueError(f"episodes must be a positive integer, got {episodes!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")


def run_episodes(policy: Policy, env_id: str, episodes: int, seed: int,
                 env_kwargs: dict[str, Any] | None = None) -> list[EpisodeResult]:
    """Run ``episodes`` episodes of ``policy`` on ``gym.make(env_id, **env_kwargs)``.

    Episode ``i`` uses reset seed ``seed + i``. The policy's ``seed(seed)`` is called first
    when it has one, and ``bind(env)`` once the env exists (for privileged policies). Raises ``TypeError`` if the policy is not a :class:`Policy` or returns
    anything but a ``str``.
    """
    if not isinstance(policy, Policy):
        raise TypeError(f"policy must have reset(instruction) and act(observation), got {type(policy).__name__}")
    check_counts(episodes, seed)
    if callable(getattr(policy, "seed", None)):
        policy.seed(seed)
    env = gym.make(env_id, **(env_kwargs or {}))
    if callable(getattr(policy, "bind", None)):
        policy.bind(env)
    results = []
    try:
        for i in range(episodes):
            obs, info = env.reset(seed=seed + i)
            policy.reset(obs["instruction"])
            total, steps, done = 0.0, 0, False
            while not done:
                action = policy.act(obs)
                if not isinstance(action, str):
                    raise TypeError(f"{type(policy).__name__}.act() must return action code (a str), "
                                    f"got {type(action).__name__}")
                obs, reward, terminated, truncated, info = env.step(action)
                total += float(reward)
                steps += 1
                done = terminated or truncated
            results.append(EpisodeResult(seed + i, obs["instruction"], bool(info["success"]), steps, total,
                                         info.get("house_seed"), info.get("distance_to_goal")))
    finally:
        env.close()
    return results


def evaluate(policy: Policy, env_id: str, episodes: int, seed: int,
             env_kwargs: dict[str, Any] | None = None) -> float:
    """The success rate of ``policy`` over ``episodes`` seeded episodes (see :func:`run_episodes`)."""
    results = run_episodes(policy, env_id, episodes, seed, env_kwargs)
    return sum(r.success for r in results) / len(results)


def expert_takeover(env_id: str, seeds, random_actions: int, action_type: str = "text") -> tuple[int, int]:
    """How the expert replans from a state it did not choose: per seed, ``random_actions``
    random steps (a move of up to 1.5 m, a turn, a tilt; one generator seeded 0 for all the
    seeds), then the expert for up to 25 actions. Returns (episodes the expert finished,
    episodes where success was still possible: not ended by the random steps)."""
    env = ExpertInfo(gym.make(env_id, width=32, height=32, action_type=action_type,
                              max_episode_steps=25 + random_actions))
    rng = np.random.default_rng(0)
    wins = possible = 0
    for seed in seeds:
        _, info = env.reset(seed=seed)
        ended = False
        for _ in range(random_actions):
            step = (MoveForward(round(float(rng.uniform(0, 1.5)), 2)), RotateRight(round(float(rng.uniform(-90, 90)), 1)),
                    RotateDown(round(float(rng.uniform(-20, 20)), 1)))
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
