"""Checks a task must pass, for a task's own tests (as PettingZoo's ``api_test``).

:func:`check_task` plays a registered task in its env: Gymnasium's ``check_env``, then
seeded episodes driven by the task expert, each played twice (a second env takes the
expert's actions), which must give the same observations, rewards, ends and infos (the
task is deterministic given the seed) and end in success (the expert completes the
task's :attr:`~legent_gym.tasks.base.Task.code`). :func:`registered_task` registers a task
for the length of a ``with`` block::

    from legent_gym.testing import check_task, registered_task

    with registered_task(MyTask):
        check_task(MyTask)

docs/adding-a-task.md walks through a new task.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils.env_checker import check_env

from legent_gym.envs.household import HouseholdEnv
from legent_gym.envs.registration import register_envs
from legent_gym.experts import Expert
from legent_gym.tasks import MAX_ACTIONS, TASKS, Task, register_task, unregister_task

__all__ = ["check_task", "registered_task", "same"]


@contextmanager
def registered_task(task: type[Task], **options: Any) -> Iterator[type[Task]]:
    """``task`` registered (:func:`~legent_gym.tasks.registry.register_task` with
    ``options``) inside the block, with its env ids once :func:`check_task` or
    :func:`~legent_gym.envs.registration.register_envs` has run; neither after it."""
    register_task(task, **options)
    try:
        yield task
    finally:
        unregister_task(task.name)
        for env_id in [env_id for env_id, spec in gym.registry.items() if spec.kwargs.get("task") == task.name]:
            del gym.registry[env_id]


def same(a: Any, b: Any) -> bool:
    """``a`` and ``b`` are equal, arrays element by element and mappings and sequences
    item by item (an observation, an info)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.dtype == b.dtype and np.array_equal(a, b)
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):
        return type(a) is type(b) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    return bool(a == b)


def _differs(what: str, seed: int, step: int, a: Any, b: Any) -> None:
    if not same(a, b):
        raise AssertionError(f"not deterministic: seed {seed}, action {step}: the two plays' {what} differ")


def check_task(task: type[Task], *, layout: str = "OneRoom", seeds: Sequence[int] = (0, 1, 2),
               action_type: str = "text", task_options: dict[str, Any] | None = None, width: int = 32,
               height: int = 32) -> dict[int, int]:
    """Check a registered task (see the module docstring) in ``layout`` over ``seeds``:
    the number of actions the expert took in each seed's episode. ``AssertionError``
    naming the seed, the action and what went wrong; ``ValueError`` for a task that is not
    registered."""
    if TASKS.get(task.name) is not task:
        raise ValueError(f"{task.__name__} is not registered with layouts as {task.name!r} (register_task)")
    register_envs()
    env_id = f"Legent/{task.name}-{layout}-v0"
    kwargs: dict[str, Any] = {"action_type": action_type, "width": width, "height": height,
                              "task_options": task_options}
    env = gym.make(env_id, render_mode="rgb_array", **kwargs)
    try:
        check_env(env.unwrapped, skip_render_check=False)
    finally:
        env.close()
    played, twin = HouseholdEnv(task.name, layout, **kwargs), HouseholdEnv(task.name, layout, **kwargs)
    try:
        expert = Expert(played)
        actions: dict[int, int] = {}
        for seed in seeds:
            first, second = played.reset(seed=seed), twin.reset(seed=seed)
            _differs("first observations and infos", seed, 0, first, second)
            info: dict[str, Any] = first[1]
            for step in range(1, MAX_ACTIONS + 1):
                action = expert.action()
                result = played.step(action)
                _differs("observations, rewards, ends and infos", seed, step, result, twin.step(action))
                info = result[4]
                if result[2] or result[3]:
                    break
            if not info["success"]:
                why = f" ({expert.problem})" if expert.problem else ""
                raise AssertionError(f"the expert did not complete {task.name} in seed {seed}'s episode within "
                                     f"{MAX_ACTIONS} actions{why}: {played.episode.require_goal().instruction!r}")
            actions[seed] = int(info["n_actions"])
        return actions
    finally:
        played.close()
        twin.close()
