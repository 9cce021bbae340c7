"""The PettingZoo envs as SuperSuit and stable-baselines3 take them: :func:`for_sb3`.

SuperSuit's ``pettingzoo_env_to_vec_env_v1`` stacks the agents into one vector env, which
needs array spaces, the same for every agent. :class:`SB3ParallelWrapper` gives each agent
what :func:`legent_gym.wrappers.for_sb3` gives the single-agent env: ``Text`` observations
as word ids (``instruction``, ``message``) and a flat ``Box(-1, 1, (4,))`` action
(move, turn right, tilt down, interact), the action limits at ``wrapper.limits``::

    import supersuit as ss
    from legent_gym.multiagent import for_sb3, parallel_env

    env = for_sb3(parallel_env(task="ComeHere", layout="OneRoom", reward="dense"))
    vec = ss.concat_vec_envs_v1(ss.pettingzoo_env_to_vec_env_v1(env), 1, num_cpus=0,
                                base_class="stable_baselines3")

One policy then plays both sides (``docs/multiagent.md`` has the whole recipe).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv
from pettingzoo.utils.wrappers import BaseParallelWrapper

from legent_gym.agent.actions import ActionLimits
from legent_gym.wrappers.sb3 import flat_action_text, token_space, tokenize_texts


class SB3ParallelWrapper(BaseParallelWrapper):
    """Each agent's ``Text`` observations as ``max_tokens`` word ids, its action a flat
    ``Box(-1, 1, (4,))`` (:func:`legent_gym.wrappers.sb3.flat_action_text`)."""

    def __init__(self, env: ParallelEnv, vocab_size: int = 1024, max_tokens: int = 16):
        super().__init__(env)
        limits = getattr(env.unwrapped, "limits", None)
        if not isinstance(limits, ActionLimits):
            raise TypeError(f"SB3ParallelWrapper needs a legent_gym PettingZoo env (one with action limits), "
                            f"got {env.unwrapped}")
        self.vocab_size, self.max_tokens = vocab_size, max_tokens
        #: The limits the flat actions are scaled to (metres, degrees).
        self.limits: ActionLimits = limits
        self._source = {agent: env.observation_space(agent) for agent in env.possible_agents}
        self.observation_spaces = {agent: token_space(space, vocab_size, max_tokens)
                                   for agent, space in self._source.items()}
        self.action_spaces = {agent: spaces.Box(-1.0, 1.0, (4,), np.float32) for agent in env.possible_agents}

    def observation_space(self, agent: str) -> spaces.Space:
        return self.observation_spaces[agent]

    def action_space(self, agent: str) -> spaces.Space:
        return self.action_spaces[agent]

    def observations(self, observations: dict[str, dict]) -> dict[str, dict]:
        """The agents' raw observations as this wrapper gives them."""
        return {agent: tokenize_texts(obs, self._source[agent], self.vocab_size, self.max_tokens)
                for agent, obs in observations.items()}

    def reset(self, seed: int | None = None, options: dict | None = None):
        observations, infos = self.env.reset(seed=seed, options=options)
        return self.observations(observations), infos

    def step(self, actions: dict[str, Any]):
        texts = {agent: flat_action_text(action, self.limits) for agent, action in actions.items()}
        observations, rewards, terminations, truncations, infos = self.env.step(texts)
        return self.observations(observations), rewards, terminations, truncations, infos


def for_sb3(env: ParallelEnv, vocab_size: int = 1024, max_tokens: int = 16) -> SB3ParallelWrapper:
    """``env`` (a parallel env of :mod:`legent_gym.multiagent`) with array spaces, the same
    for both agents, for SuperSuit's ``pettingzoo_env_to_vec_env_v1`` and stable-baselines3."""
    return SB3ParallelWrapper(env, vocab_size, max_tokens)
