"""legent_gym: Gymnasium + PettingZoo environments for embodied agents in homes, on MuJoCo.

Layers, from the bottom:

* :mod:`legent_gym.world`: scene format, asset library, MuJoCo builder, rendering,
  navigation and house generation. Knows nothing of Gymnasium.
* :mod:`legent_gym.tasks`: what the agent is asked to do and how success is judged.
* :mod:`legent_gym.envs`: Gymnasium environments that join a world, an agent and a task.
* :mod:`legent_gym.experts` and :mod:`legent_gym.wrappers`: expert policies and wrappers.
"""

from legent_gym import gl_backend  # noqa: F401  (must run before mujoco is imported)

__version__ = "0.1.0"

from legent_gym.envs.registration import ENV_IDS, register_envs  # noqa: E402

register_envs()

__all__ = ["ENV_IDS", "__version__"]
