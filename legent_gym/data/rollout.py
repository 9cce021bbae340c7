"""Running one episode with a policy and keeping everything the exports need.

A policy is a callable ``(obs, info) -> action`` in the env's own action space. The
default, :func:`expert_policy`, plays ``info["expert_action"]``, which the
:class:`~legent_gym.wrappers.expert.ExpertInfo` wrapper puts into every info.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import gymnasium as gym
import numpy as np

from legent_gym.tasks.registry import paper_instruction
from legent_gym.wrappers.expert import ExpertInfo

Policy = Callable[[dict, dict], Any]

#: The ``--policy`` name of the expert (any other name is ``module:function``).
EXPERT = "expert"


def expert_policy(obs: dict, info: dict) -> Any:
    """Play the expert's action (needs the env wrapped in ``ExpertInfo``)."""
    try:
        return info["expert_action"]
    except KeyError:
        raise KeyError("info has no 'expert_action': wrap the env in "
                       "legent_gym.wrappers.expert.ExpertInfo to play the expert") from None


def resolve_policy(name: str) -> Policy:
    """``"expert"`` or ``"package.module:function"`` -> the policy callable."""
    if name == EXPERT:
        return expert_policy
    module_name, sep, attr = name.partition(":")
    if not sep or not module_name or not attr:
        raise ValueError(f"policy must be 'expert' or 'module:function', got {name!r}")
    try:
        module = importlib.import_module(module_name)
    except ImportError as err:
        raise ValueError(f"policy {name!r}: cannot import module {module_name!r} ({err})") from err
    policy = getattr(module, attr, None)
    if not callable(policy):
        raise ValueError(f"policy {name!r}: module {module_name!r} has no callable {attr!r}")
    return policy


def make_env(env_id: str, env_kwargs: dict[str, Any] | None = None, *, expert: bool = False,
             find_strategy: str = "direct") -> gym.Env:
    """``gym.make(env_id, **env_kwargs)``, wrapped in ``ExpertInfo`` (with the expert's
    ``find_strategy``) when the expert plays."""
    env = gym.make(env_id, **(env_kwargs or {}))
    if expert:
        env = ExpertInfo(env, find_strategy)
    return env


def recorded_info(info: dict) -> dict[str, Any]:
    """The privileged state kept per step, with the same keys and types at reset and step
    (Minari stores infos as columns, so they must not change shape)."""
    distance = info.get("distance_to_goal")
    held = info.get("held")
    return {
        "success": bool(info.get("success", False)),
        "distance_to_goal": math.nan if distance is None else float(distance),
        "agent_pose": np.asarray(info["agent_pose"], dtype=np.float64),
        "user_pose": np.asarray(info.get("user_pose", (math.nan,) * 4), dtype=np.float64),
        "held": -1 if held is None else int(held),
        "n_actions": int(info.get("n_actions", 0)),
    }


@dataclass
class Episode:
    """One attempt: ``observations`` has one more entry than ``actions`` (the view after
    the last action). ``action_texts`` are LEGENT's action code for each step."""

    attempt: int
    seed: int
    env_id: str
    instruction: str
    task: dict[str, Any]
    observations: list[dict[str, Any]] = field(default_factory=list)
    actions: list[Any] = field(default_factory=list)
    action_texts: list[str] = field(default_factory=list)
    rewards: list[float] = field(default_factory=list)
    terminations: list[bool] = field(default_factory=list)
    truncations: list[bool] = field(default_factory=list)
    infos: list[dict[str, Any]] = field(default_factory=list)
    #: Per step, the expert's action (code) where a perturbation was executed in its place
    #: (``record_episode(perturb=...)``) or at every step (``expert_labels=True``, DAgger),
    #: else None. The view before such a step is a state the policy reached; the expert's
    #: action there is its label, what was executed is not.
    labels: list[str | None] = field(default_factory=list)
    #: Per observation, ``info["goal_view"]`` (the goal's visibility, bearing and distance
    #: from that view; :class:`~legent_gym.experts.oracle.GoalView`) where the env provides
    #: it (``ExpertInfo``), else None.
    goal_views: list[dict[str, Any] | None] = field(default_factory=list)
    #: Per step, the agent's views of the moments within it, before its observation
    #: (``info["frames"]`` of an env with ``frames_per_step`` > 1; else empty lists).
    between: list[list[np.ndarray]] = field(default_factory=list)
    success: bool = False
    house_seed: int | None = None
    scene_name: str | None = None
    #: The goal in the paper's template words (LEGENT's ``task``; see :func:`begin_episode`).
    paper_instruction: str = ""

    @property
    def steps(self) -> int:
        return len(self.actions)

    @property
    def path(self) -> list[tuple[float, float]]:
        """The agent's positions, from the start to the end."""
        return [(float(i["agent_pose"][0]), float(i["agent_pose"][1])) for i in self.infos]


def begin_episode(env: gym.Env, obs: dict, info: dict, *, attempt: int, seed: int, env_id: str) -> Episode:
    """The record of an episode ``env`` was just reset to (``obs``, ``info``), with its first
    observation. The goal comes from the env's episode engine (``env.unwrapped.episode``):
    ``task`` is the task's name and the goal's own description (None for an id it has not,
    WhereIs's ``answers`` a list, where ``info["task"]`` has -1 and one string), with the
    goal in the paper's words (:func:`~legent_gym.tasks.registry.paper_instruction`)."""
    engine = getattr(env.unwrapped, "episode", None)  # HouseholdEnv's, SingleAgentEnv's
    if engine is None:
        raise TypeError(f"recording needs a legent_gym env (one with an episode engine), got {env.unwrapped}")
    goal = engine.require_goal()
    episode = Episode(attempt=attempt, seed=seed, env_id=env_id, instruction=str(obs["instruction"]),
                      task={"name": info["task"]["name"], **goal.describe()}, house_seed=engine.house_seed,
                      scene_name=info.get("scene_name"),
                      paper_instruction=paper_instruction(engine.task, goal, engine.require()))
    episode.observations.append(obs)
    episode.infos.append(recorded_info(info))
    episode.goal_views.append(info.get("goal_view"))
    return episode


def _action_text(action: Any, info: dict) -> str:
    # The env reports the executed action as canonical code; an unparsable text action
    # executes nothing and reports "", so keep what the policy wrote.
    text = info.get("action_text")
    if text:
        return text
    return action if isinstance(action, str) else str(action)


def perturbation(rng: np.random.Generator) -> str:
    """A random navigation step in the expert's own step shapes (so it adds no new template
    to a model's history): a turn of up to 90 degrees either way (half the time), a move of
    0.3-2 m (a quarter), or a move then a turn (a quarter). Moves often end against
    furniture: the states a cloned policy gets stuck in, which clean demonstrations never show."""
    turn = f"rotate_right({round(float(rng.uniform(-90.0, 90.0)), 1) + 0.0!r})"
    move = f"move_forward({round(float(rng.uniform(0.3, 2.0)), 2)!r})"
    kind = rng.random()
    return turn if kind < 0.5 else move if kind < 0.75 else f"{move}, {turn}"


def _perturbation_rng(seed: int) -> np.random.Generator:
    return np.random.default_rng([seed, 0x9E7])  # its own stream: the env's seed alone fixes it


def _expert_label(info: dict) -> str:
    if "expert_action" not in info:
        raise KeyError("expert labels need info['expert_action']: wrap the env in ExpertInfo")
    expert = info["expert_action"]
    if not isinstance(expert, str):
        raise TypeError("expert labels need text actions (action_type='text')")
    return expert


def record_episode(env: gym.Env, policy: Policy, *, seed: int, attempt: int, env_id: str,
                   perturb: float = 0.0, expert_labels: bool = False) -> Episode:
    """Reset with ``seed`` and play ``policy`` until the episode ends.

    ``perturb``: the probability, per step, of executing a random :func:`perturbation`
    instead of the policy's action (DART-style recovery data: the expert, replanning from
    wherever the perturbation left the agent, labels the states off its own path). Such a
    step records the perturbation in ``actions``/``action_texts`` (what happened) and the
    expert's action (``info["expert_action"]``, which the env must provide) in ``labels``.
    The perturbations depend on ``seed`` alone. Text actions only.

    ``expert_labels``: label *every* step with the expert's action (DAgger: the policy
    drives, the expert says what it should have done in each state it reached)."""
    if not 0.0 <= perturb < 1.0:
        raise ValueError(f"perturb must be in [0, 1), got {perturb}")
    rng = _perturbation_rng(seed) if perturb > 0 else None
    obs, info = env.reset(seed=seed)
    episode = begin_episode(env, obs, info, attempt=attempt, seed=seed, env_id=env_id)
    while True:
        action = policy(obs, info)
        perturbed = False
        if rng is not None and rng.random() < perturb:
            perturbed, action = True, perturbation(rng)
        label = _expert_label(info) if perturbed or expert_labels else None
        obs, reward, terminated, truncated, info = env.step(action)
        episode.actions.append(action)
        episode.labels.append(label)
        episode.action_texts.append(_action_text(action, info))
        episode.rewards.append(float(reward))
        episode.terminations.append(bool(terminated))
        episode.truncations.append(bool(truncated))
        episode.between.append(list(info.get("frames", ())))
        episode.observations.append(obs)
        episode.infos.append(recorded_info(info))
        episode.goal_views.append(info.get("goal_view"))
        if terminated or truncated:
            break
    episode.success = bool(info.get("success", False))
    return episode
