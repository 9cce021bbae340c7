"""One side of the multi-agent env as a single-agent Gymnasium env; the other side is fixed.

    env = make_single_agent("Legent/ComeHere-TwoRoom-v0", partner="wander")    # learn the agent
    env = SingleAgentEnv(parallel_env(task="ComeHere"), partner=agent_policy, learner="user")

With ``partner="still"`` and ``learner="agent"`` it is the single-agent env: the same
observations, rewards and infos under the same seed (``tests/multiagent/test_multiagent.py``).
The partner is reset at every episode with a generator drawn from this env's own seed, so
its randomness never changes which houses are drawn.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from legent_gym.envs.episode import Episode
from legent_gym.multiagent.household import AGENT, USER, HouseholdParallelEnv
from legent_gym.multiagent.user_policies import StandStill, UserPolicy, make_policy


class SingleAgentEnv(gym.Env):
    """``learner`` (``"agent"`` or ``"user"``) acts through ``step``; ``partner`` (a policy
    name, a :class:`UserPolicy`, or a function ``observation -> action``) plays the other."""

    def __init__(self, env: HouseholdParallelEnv, partner: UserPolicy | str | Any = "still", learner: str = AGENT):
        if learner not in (USER, AGENT):
            raise ValueError(f"learner must be {USER!r} or {AGENT!r}, got {learner!r}")
        if not isinstance(env.unwrapped, HouseholdParallelEnv):
            raise TypeError(f"expected a HouseholdParallelEnv (parallel form), got {type(env).__name__}")
        self.parallel_env = env
        self.learner = learner
        self.partner_name = USER if learner == AGENT else AGENT
        self.partner = make_policy(partner)
        self.observation_space = env.observation_space(learner)
        self.action_space = env.action_space(learner)
        self.metadata = {"render_modes": list(env.metadata["render_modes"]), "render_fps": env.metadata["render_fps"]}
        self.render_mode = env.render_mode
        self.action_type: str = env.unwrapped.action_type
        self.task_name: str = env.unwrapped.task_name
        self._partner_obs: dict[str, Any] | None = None

    @property
    def episode(self) -> Episode:
        """The episode engine both sides act in (what the experts' Oracle reads)."""
        return self.parallel_env.unwrapped.episode

    def set_partner(self, partner: UserPolicy | str | Any) -> None:
        """Play against another fixed policy from now on (mid-episode too: it is reset now)."""
        self.partner = make_policy(partner)
        if self._partner_obs is not None:
            self.partner.reset(self.parallel_env.unwrapped, np.random.default_rng(int(self.np_random.integers(2**63 - 1))))

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        observations, infos = self.parallel_env.reset(seed=seed, options=options)
        self.partner.reset(self.parallel_env.unwrapped, np.random.default_rng(int(self.np_random.integers(2**63 - 1))))
        self._partner_obs = observations[self.partner_name]
        return observations[self.learner], infos[self.learner]

    def step(self, action):
        if self._partner_obs is None:
            raise RuntimeError("call reset() before step()")
        partner_action = self.partner.act(self.parallel_env.unwrapped, self._partner_obs)
        observations, rewards, terminations, truncations, infos = self.parallel_env.step(
            {self.learner: action, self.partner_name: partner_action})
        self._partner_obs = observations[self.partner_name]
        me = self.learner
        return observations[me], rewards[me], terminations[me], truncations[me], infos[me]

    def render(self):
        return self.parallel_env.render()

    def close(self):
        self.parallel_env.close()


def make_single_agent(env_id: str, partner: UserPolicy | str | Any = "still", learner: str = AGENT,
                      **kwargs: Any) -> SingleAgentEnv:
    """A registered multi-agent id (``pettingzoo.make("parallel", env_id, **kwargs)``) with
    one side fixed. A user that stands still (``partner="still"`` or a ``StandStill``; it
    only turns) is drawn as one mesh, as in the single-agent envs (``user_moves=False``),
    unless ``user_moves`` is given."""
    # pettingzoo: the multiagent extra
    import pettingzoo

    if learner == AGENT and (partner == "still" or isinstance(partner, StandStill)):
        kwargs.setdefault("user_moves", False)
    return SingleAgentEnv(pettingzoo.make("parallel", env_id, **kwargs), partner=partner, learner=learner)
