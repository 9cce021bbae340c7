"""The multi-agent ids in PettingZoo's registry, under "parallel" and "aec".

The ids are the single-agent ones (``Legent/<Task>-<Layout>-v0``, the same table): the same
task in the same houses, with the user acting. Registered when :mod:`legent_gym.multiagent`
is imported::

    import pettingzoo, legent_gym.multiagent
    env = pettingzoo.make("parallel", "Legent/ComeHere-OneRoom-v0")

Entry points are strings, so the registry imports nothing until an env is made.
"""

from __future__ import annotations

import pettingzoo

from legent_gym.envs.registration import ENV_IDS, id_kwargs
from legent_gym.tasks import MAX_ACTIONS

MULTIAGENT_ENV_IDS: tuple[str, ...] = ENV_IDS
ENTRY_POINTS = {"parallel": "legent_gym.multiagent.household:parallel_env",
                "aec": "legent_gym.multiagent.household:env"}

__all__ = ["ENTRY_POINTS", "MULTIAGENT_ENV_IDS", "id_kwargs", "register_multiagent_envs"]


def register_multiagent_envs() -> None:
    registries = {"parallel": pettingzoo.parallel_registry, "aec": pettingzoo.aec_registry}
    for env_id in MULTIAGENT_ENV_IDS:
        for env_type, entry_point in ENTRY_POINTS.items():
            if env_id not in registries[env_type]:
                pettingzoo.register(env_type, env_id, entry_point=entry_point, kwargs=id_kwargs(env_id),
                                    max_cycles=MAX_ACTIONS)
