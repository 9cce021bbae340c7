"""Table-driven registration of every environment id (run on ``import legent_gym``).

Ids are ``Legent/<Task>-<Layout>-v0``. Both action spaces come from the same id:
``gym.make(id)`` gives the text actions, ``gym.make(id, action_type="continuous")`` the
Dict actions. Entry points are strings so that ``EnvSpec.to_json()`` works (Minari needs it).
"""

from __future__ import annotations

import gymnasium as gym

TASKS = ("ComeHere", "GoTo", "PickUp", "BringMe", "WhereIs", "PutOn")
LAYOUTS = ("OneRoom", "TwoRoom", "FourRoom")
MAX_EPISODE_STEPS = 25  # the paper's evaluation cap

ENV_IDS: tuple[str, ...] = tuple(f"Legent/{task}-{layout}-v0" for task in TASKS for layout in LAYOUTS)


def register_envs() -> None:
    for task in TASKS:
        for layout in LAYOUTS:
            env_id = f"Legent/{task}-{layout}-v0"
            if env_id in gym.registry:
                continue
            gym.register(
                id=env_id,
                entry_point="legent_gym.envs.household:HouseholdEnv",
                kwargs={"task": task, "layout": layout},
                max_episode_steps=MAX_EPISODE_STEPS,
                disable_env_checker=False,
            )
