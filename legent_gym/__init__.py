"""legent_gym: Gymnasium + PettingZoo environments for embodied agents in homes, on MuJoCo.

``import legent_gym`` registers the ``Legent/*`` ids (:data:`ENV_IDS`) with Gymnasium. What
each package and module holds: the README's layout table; why the layers are what they
are: ``docs/architecture.md``.
"""

from legent_gym.utils import gl_backend  # noqa: F401  (must run before mujoco is imported)

__version__ = "0.1.0"

from legent_gym.envs.registration import ENV_IDS, register_envs  # noqa: E402

register_envs()

__all__ = ["ENV_IDS", "__version__"]
