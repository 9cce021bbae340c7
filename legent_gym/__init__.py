"""legent_gym: Gymnasium + PettingZoo environments for embodied agents in homes, on MuJoCo.

Layers, from the bottom (``docs/architecture.md`` has the map and the reasons):

* :mod:`legent_gym.world`: scene format, wall/door/footprint geometry
  (``world/geometry.py``), asset library (``world/assets``), MuJoCo builder, rendering,
  navigation and house generation (``world/generation``). Knows nothing of Gymnasium.
* :mod:`legent_gym.agent`: the body and the action language.
* :mod:`legent_gym.tasks`: what the agent is asked to do and how success is judged.
* :mod:`legent_gym.envs`: the episode engine without Gymnasium (``envs/episode.py``: house
  draw, set-up, executing a body's primitives, judging, observing) and ``HouseholdEnv``,
  the Gymnasium env on it.
* :mod:`legent_gym.multiagent`: PettingZoo envs where the user acts too, and one side of
  them as a Gymnasium env.
* :mod:`legent_gym.experts`: the task experts, which read privileged state through
  ``Oracle`` alone.
* :mod:`legent_gym.wrappers`: expert labels, SB3 adapters, interleaved history.
* :mod:`legent_gym.hyperparams`: RL Baselines3 Zoo's hyperparameters (``ppo.yml``).
* :mod:`legent_gym.data`: ``legent-gym collect`` (Minari, LEGENT's format, video).
* :mod:`legent_gym.play`: ``legent-gym play``, a person playing the user or the agent in
  the browser (WebSocket server, sessions, recording).
* :mod:`legent_gym.llm`: the LLM features: one chat client, the prompts, scenes from text,
  task generation, asset annotation.

* :mod:`legent_gym.utils`: GL backend choice, atomic writes, worker processes, Ray.

Top-level modules: :mod:`legent_gym.cli` (the ``legent-gym`` command) and
:mod:`legent_gym.errors` (``UserError``).
"""

from legent_gym.utils import gl_backend  # noqa: F401  (must run before mujoco is imported)

__version__ = "0.1.0"

from legent_gym.envs.registration import ENV_IDS, register_envs  # noqa: E402

register_envs()

__all__ = ["ENV_IDS", "__version__"]
