"""The user and the agent, both learnable: PettingZoo environments (needs the ``multiagent`` extra).

* :mod:`~legent_gym.multiagent.household`: :class:`HouseholdParallelEnv` and the module
  functions ``parallel_env()``, ``raw_env()``, ``env()`` (PettingZoo's parallel and AEC forms);
* :mod:`~legent_gym.multiagent.user_policies`: scripted users (stand still, wander, walk
  away, come towards the agent, repeat the instruction);
* :mod:`~legent_gym.multiagent.single_agent`: one side as a Gymnasium env, the other fixed;
* :mod:`~legent_gym.multiagent.sb3`: :func:`for_sb3`, array spaces for SuperSuit and stable-baselines3;
* :mod:`~legent_gym.multiagent.registration`: the ids in PettingZoo's registry (done on import).
"""

try:
    import pettingzoo  # noqa: F401
except ImportError as err:  # an optional extra: say how to get it
    raise ImportError("legent_gym.multiagent needs PettingZoo: pip install 'legent-gym[multiagent]'") from err

from legent_gym.multiagent.household import (  # noqa: E402
    AGENT,
    USER,
    HouseholdParallelEnv,
    env,
    env_module,
    parallel_env,
    raw_env,
)
from legent_gym.multiagent.registration import MULTIAGENT_ENV_IDS, register_multiagent_envs
from legent_gym.multiagent.sb3 import SB3ParallelWrapper, for_sb3
from legent_gym.multiagent.single_agent import SingleAgentEnv, make_single_agent
from legent_gym.multiagent.user_policies import (
    USER_POLICIES,
    ComeTowards,
    RepeatInstruction,
    StandStill,
    UserPolicy,
    WalkAway,
    Wander,
    make_policy,
)

register_multiagent_envs()

__all__ = [
    "AGENT",
    "MULTIAGENT_ENV_IDS",
    "USER",
    "USER_POLICIES",
    "ComeTowards",
    "HouseholdParallelEnv",
    "RepeatInstruction",
    "SB3ParallelWrapper",
    "SingleAgentEnv",
    "StandStill",
    "UserPolicy",
    "WalkAway",
    "Wander",
    "env",
    "env_module",
    "for_sb3",
    "make_policy",
    "make_single_agent",
    "parallel_env",
    "raw_env",
    "register_multiagent_envs",
]
