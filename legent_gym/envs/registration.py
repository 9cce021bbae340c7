"""Table-driven registration of every environment id (run on ``import legent_gym``).

Ids are ``Legent/<Task>-<Layout>-v0`` for every task of :data:`legent_gym.tasks.TASKS` and
every layout of :data:`LAYOUTS`, and ``Legent/Custom-v0`` (:data:`SCENE_TASK_IDS`: tasks
from a file, in a given scene), capped at :data:`legent_gym.tasks.MAX_ACTIONS` actions.
Both action spaces come from the same id: ``gym.make(id)`` gives the text actions,
``gym.make(id, action_type="continuous")`` the Dict actions. Entry points are strings so
that ``EnvSpec.to_json()`` works (Minari needs it). Every id has the vector entry point
:data:`VECTOR_ENTRY_POINT`: ``gym.make_vec(id, N, vectorization_mode="vector_entry_point")``
(and ``gym.make_vec(id, N)`` with no mode) gives
:class:`legent_gym.envs.shared_vector.SharedMemoryVectorEnv`. A task registered after
``import legent_gym`` (one defined outside the package) gets its ids when
:func:`register_envs` runs again.
"""

from __future__ import annotations

import gymnasium as gym

from legent_gym.tasks import MAX_ACTIONS
from legent_gym.tasks import TASKS as TASK_TABLE

#: The registered tasks, in the task table's order.
TASKS: tuple[str, ...] = tuple(TASK_TABLE)
#: The generation presets that get ids (``Apartment`` is a preset too, reached with ``layout=``).
LAYOUTS = ("OneRoom", "TwoRoom", "FourRoom")


def id_table() -> tuple[tuple[str, str, str], ...]:
    """(env id, task, layout) for every task registered now and every layout."""
    return tuple((f"Legent/{task}-{layout}-v0", task, layout) for task in TASK_TABLE for layout in LAYOUTS)


#: (env id, task, layout) for every id of the built-in tasks.
ID_TABLE: tuple[tuple[str, str, str], ...] = id_table()
ENV_IDS: tuple[str, ...] = tuple(env_id for env_id, _, _ in ID_TABLE)
#: (env id, task) of the ids whose tasks are read from a file for one scene: they take
#: ``scene=`` and ``tasks=`` (see :mod:`legent_gym.tasks.custom`), so they are not among
#: :data:`ENV_IDS`, whose every id makes an env with no arguments.
SCENE_TASK_IDS: tuple[tuple[str, str], ...] = (("Legent/Custom-v0", "Custom"),)
#: Every id's ``vector_entry_point`` (``gym.make_vec(id, num_envs, vectorization_mode=
#: "vector_entry_point")``): :func:`legent_gym.envs.shared_vector.make_vector`.
VECTOR_ENTRY_POINT = "legent_gym.envs.shared_vector:make_vector"


def id_kwargs(env_id: str) -> dict[str, str]:
    """``{"task": ..., "layout": ...}`` of a registered id."""
    table = id_table()
    for known, task, layout in table:
        if env_id == known:
            return {"task": task, "layout": layout}
    raise ValueError(f"unknown env id {env_id!r}; known: {', '.join(known for known, _, _ in table)}")


def register_envs() -> None:
    """Register the ids of every task registered now (those registered already are kept)."""
    for env_id, task, layout in id_table():
        if env_id in gym.registry:
            continue
        gym.register(
            id=env_id,
            entry_point="legent_gym.envs.household:HouseholdEnv",
            kwargs={"task": task, "layout": layout},
            max_episode_steps=MAX_ACTIONS,
            disable_env_checker=False,
            vector_entry_point=VECTOR_ENTRY_POINT,
        )
    for env_id, task in SCENE_TASK_IDS:
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point="legent_gym.envs.household:HouseholdEnv", kwargs={"task": task},
                         max_episode_steps=MAX_ACTIONS, disable_env_checker=False,
                         vector_entry_point=VECTOR_ENTRY_POINT)
