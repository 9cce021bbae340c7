"""One env process per core: how the envs of a vector env share a multi-core machine.

Gymnasium's ``AsyncVectorEnv`` (``gym.make_vec(id, num_envs=N, vectorization_mode="async")``)
and stable-baselines3's ``SubprocVecEnv`` run each env in a process of its own. Left alone,
the processes wander between cores and each one's software renderer (Mesa's llvmpipe)
starts a pool of rasterising threads as large as the machine, so N processes fight over
the cores with N times that many threads. :func:`settle_worker` is called when an env is
made (``HouseholdEnv(pin_worker=True)``, the default): in such a worker process it pins the
process to one core (the worker's number modulo the cores the process may use) and makes
llvmpipe render in the calling thread; on a machine with several NVIDIA GPUs it also
gives the worker a GPU to render on (``gl_backend.assign_egl_device``: round robin, unless
``MUJOCO_EGL_DEVICE_ID`` is set). It does nothing in the main process, in a process
already pinned to one core (``legent_gym.utils.workers`` pins its own), or where the operating
system has no CPU affinity.
"""

from __future__ import annotations

import multiprocessing
import os
import re

from legent_gym.utils import gl_backend

#: A multiprocessing child's name ends in its number: Gymnasium names its workers
#: ``Worker<AsyncVectorEnv>-i``, and the standard library numbers the others.
_NUMBER = re.compile(r"-(\d+)$")


def worker_number() -> int | None:
    """This process's number among its parent's multiprocessing children, or None when it
    is not such a child."""
    if multiprocessing.parent_process() is None:
        return None
    match = _NUMBER.search(multiprocessing.current_process().name)
    return int(match.group(1)) if match else None


def settle_worker() -> int | None:
    """In a vector env's worker process: pin it to one core and keep llvmpipe to the
    calling thread (see the module docstring). Returns the core, or None if nothing was
    done."""
    number = worker_number()
    if number is None:
        return None
    gl_backend.assign_egl_device(number)
    if not hasattr(os, "sched_setaffinity"):
        return None
    cores = sorted(os.sched_getaffinity(0))
    if len(cores) < 2:
        return None
    core = cores[number % len(cores)]
    os.sched_setaffinity(0, {core})
    # Read when the OpenGL driver loads, at the first frame: no context exists yet.
    gl_backend.draw_in_calling_thread()
    return core
