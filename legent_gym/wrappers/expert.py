"""Expert wrappers, for imitation learning and demonstrations.

* :class:`ExpertInfo` adds ``info["expert_action"]``: the task expert's next action, in the
  env's own action space (action code for ``action_type="text"``, a dict for
  ``"continuous"``), at reset and after every step, whatever action was taken. With it a
  DAgger loop labels the states its own policy visits.
* :class:`ExpertPolicy` executes the expert's action instead of the one passed to
  ``step`` (pass ``None``), for collecting demonstrations; ``info["expert_action"]`` is the
  action about to be taken and ``info["action_taken"]`` the one just taken.

``info["goal_view"]`` is the :class:`~legent_gym.experts.oracle.GoalView` of the task's
current goal as a dict (``visible``, ``bearing``, ``distance``): privileged labels that
``legent-gym collect`` stores per step for auxiliary training targets.

When the expert cannot plan (the goal became unreachable) its action is ``finish()`` and
``info["expert_problem"]`` says why; otherwise ``info["expert_problem"]`` is ``""``.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym

from legent_gym.envs.action_spaces import noop_dict
from legent_gym.experts.expert import Expert


class ExpertInfo(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """Adds ``info["expert_action"]`` (and ``info["expert_problem"]``, ``info["goal_view"]``)
    at reset and every step.

    ``find_strategy``: passed to :class:`~legent_gym.experts.expert.Expert`."""

    def __init__(self, env: gym.Env, find_strategy: str = "direct"):
        gym.utils.RecordConstructorArgs.__init__(self, find_strategy=find_strategy)
        gym.Wrapper.__init__(self, env)
        self.expert = Expert(env, find_strategy)

    def _label(self, info: dict[str, Any]) -> dict[str, Any]:
        info = dict(info)
        info["expert_action"] = self.expert.action()
        info["expert_problem"] = self.expert.problem or ""
        info["goal_view"] = self.expert.oracle.goal_view().to_dict()
        return info

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        return obs, self._label(info)

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        return obs, reward, terminated, truncated, self._label(info)


class ExpertPolicy(ExpertInfo):
    """Steps with the expert's action; the action passed to :meth:`step` is ignored (pass
    ``None``). ``info["action_taken"]`` is the action executed (at reset: the no-op, ``""``
    or :func:`~legent_gym.envs.action_spaces.noop_dict`).

    The env below records what it is stepped with, so a recorder of actions goes *inside*:
    ``ExpertPolicy(minari.DataCollector(env))`` records the expert's actions (a
    ``DataCollector`` outside would record the ``None`` passed to this wrapper)."""

    def reset(self, **kwargs):
        obs, info = super().reset(**kwargs)
        self._next = info["expert_action"]
        info["action_taken"] = "" if isinstance(self._next, str) else noop_dict()
        return obs, info

    def step(self, action=None):
        taken = self._next
        obs, reward, terminated, truncated, info = super().step(taken)
        info["action_taken"] = taken
        self._next = info["expert_action"]
        return obs, reward, terminated, truncated, info
