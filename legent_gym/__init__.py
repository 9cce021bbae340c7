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

Top-level modules: :mod:`legent_gym.cli` (the ``legent-gym`` command),
:mod:`legent_gym.gl_backend` (picks EGL before MuJoCo is imported),
:mod:`legent_gym.atomic` (atomic file writes), :mod:`legent_gym.heap`
(the C heap's freed pages handed back after a dropped house), :mod:`legent_gym.workers` (worker processes:
forkserver, one core each, results in order), :mod:`legent_gym.scale` (the same as Ray
tasks, on one machine or a cluster).
"""

from legent_gym import gl_backend  # noqa: F401  (must run before mujoco is imported)

__version__ = "0.1.0"

from legent_gym.envs.registration import ENV_IDS, register_envs  # noqa: E402

register_envs()

__all__ = ["ENV_IDS", "__version__"]
