"""Where the project's parallel loops run: worker processes here, or Ray tasks on a cluster.

:func:`legent_gym.utils.workers.map_ordered` takes a ``backend``: ``"process"`` (the default:
forkserver worker processes on this machine, see :mod:`legent_gym.utils.workers`) or
:class:`Backend` ``("ray", address)``. Both keep the same contract: ``fn(*call)`` for each
call, results yielded in the order of the calls, at most ``ahead * workers`` calls handed
out beyond the last result yielded, the first error raised at once. So a caller that
commits results in order (``legent-gym collect``, the evaluations) writes the same output
whichever backend computed them.

On Ray each call is one task (``max_retries``: a task whose worker process dies, killed
or out of memory, runs again elsewhere; an exception raised by ``fn`` is not retried and
reaches the caller). A task returns its result whole to the driver (the process that
called ``map_ordered``), or nothing if it dies, so a result is never half there. Each Ray
worker process runs ``initializer(*initargs)`` once per map before its first call of that
map (an env, a loaded checkpoint stay for the next calls) and renders with llvmpipe in its
own thread (``LP_NUM_THREADS=0``), as a process worker does.

``address`` is ``"auto"`` (the cluster this machine belongs to, ``ray start``), ``HOST:PORT``
(its head) or ``None``: start a Ray on this machine, bound to the loopback interface, with
``workers`` CPUs and no dashboard. If this process is connected to Ray already
(``ray.init`` was called), that connection is used. Ray is the optional ``scale`` extra:
``pip install -e ".[scale]"``. See ``docs/scale.md``.
"""

from __future__ import annotations

import importlib
import importlib.util
import logging
import os
import sys
import uuid
from collections import deque
from collections.abc import Callable, Generator, Iterable
from dataclasses import dataclass
from typing import Any

from legent_gym.utils import gl_backend

__all__ = ["BACKENDS", "Backend", "BackendUnavailable", "RAY_TASK_RETRIES", "connect_ray", "in_call_order",
           "ray_results", "require_ray"]

BACKENDS = ("process", "ray")
#: How often a Ray task runs again after its worker process died.
RAY_TASK_RETRIES = 5
RAY_MISSING = 'the ray backend needs Ray, which the "scale" extra installs: pip install -e ".[scale]"'


class BackendUnavailable(RuntimeError):
    """The backend asked for cannot run here (Ray is not installed)."""


@dataclass(frozen=True)
class Backend:
    """Where calls run: ``kind`` ``"process"`` or ``"ray"``; ``address`` (Ray only) as in the
    module's docstring."""

    kind: str = "process"
    address: str | None = None

    def __post_init__(self) -> None:
        if self.kind not in BACKENDS:
            raise ValueError(f"backend must be one of {', '.join(BACKENDS)}, got {self.kind!r}")
        if self.address is not None and self.kind != "ray":
            raise ValueError("a Ray address needs the ray backend")
        if self.address is not None and self.address != "auto" and not _host_port(self.address):
            raise ValueError(f"the Ray address must be 'auto' or HOST:PORT, got {self.address!r}")

    @classmethod
    def of(cls, backend: Backend | str | None) -> Backend:
        if backend is None:
            return cls()
        return backend if isinstance(backend, Backend) else cls(backend)

    def check(self) -> None:
        """Raise :class:`BackendUnavailable` now if this backend cannot run here. Ray is
        looked for, not imported: :func:`connect_ray` sets its environment first."""
        if self.kind == "ray" and importlib.util.find_spec("ray") is None:
            raise BackendUnavailable(RAY_MISSING)


def _host_port(address: str) -> bool:
    host, _, port = address.rpartition(":")
    return bool(host) and port.isdigit() and 0 < int(port) < 65536


def require_ray() -> Any:
    """The ``ray`` module, or :class:`BackendUnavailable` saying which extra installs it."""
    try:
        return importlib.import_module("ray")
    except ImportError:
        raise BackendUnavailable(RAY_MISSING) from None


def connect_ray(address: str | None, workers: int) -> Any:
    """Connect this process to Ray (see the module's docstring) and return the module."""
    if address is None and "ray" not in sys.modules:
        # Read when ray is imported: a Ray started here then binds and advertises the
        # loopback interface only (one machine; nothing to reach from outside).
        os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")
        os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    ray = require_ray()
    if ray.is_initialized():
        return ray
    if address is None:
        # "local": a new Ray, even where RAY_ADDRESS or a `ray start` cluster would be joined.
        ray.init(address="local", num_cpus=workers, include_dashboard=False, _node_ip_address="127.0.0.1",
                 logging_level=logging.WARNING)
    else:
        ray.init(address=address, logging_level=logging.WARNING)
    return ray


_remote: Any = None


def _task(ray: Any) -> Any:
    global _remote
    if _remote is None:
        _remote = ray.remote(_run_call).options(max_retries=RAY_TASK_RETRIES, retry_exceptions=False,
                                                num_cpus=1)
    return _remote


def in_call_order(calls: Iterable[tuple], limit: int, submit: Callable[[tuple], Any],
                  wait_first: Callable[[deque], None], result: Callable[[Any], Any],
                  pending: deque) -> Generator[Any, None, None]:
    """The ordered map of both backends: ``submit(call)`` keeps at most ``limit`` calls in
    flight in ``pending`` (the caller's, so that its clean-up sees what is left), and the
    results are yielded in call order: ``wait_first(pending)`` waits for the first (raising a
    later call's error at once) and ``result`` takes it."""
    calls = iter(calls)
    while True:
        while len(pending) < limit:
            call = next(calls, None)
            if call is None:
                break
            pending.append(submit(tuple(call)))
        if not pending:
            return
        wait_first(pending)
        yield result(pending.popleft())


def ray_results(fn: Callable[..., Any], calls: Iterable[tuple], *, workers: int,
                initializer: Callable[..., Any] | None, initargs: tuple, ahead: int,
                address: str | None) -> Generator[Any, None, None]:
    """``fn(*call)`` for each call, computed by Ray tasks, yielded in order (the contract of
    :func:`legent_gym.utils.workers.map_ordered`)."""
    ray = connect_ray(address, workers)
    task = _task(ray)
    setup = ray.put((uuid.uuid4().hex, fn, initializer, initargs))
    # The calls still in flight when the map ends early (at most ``ahead * workers``) are left
    # to finish, their results unread: ray.cancel of a task whose reply is on its way aborts
    # the driver process in Ray 2.60 (a failed check in TaskManager::CompletePendingTask).
    # A Ray started here stops with this process, and its tasks with it.
    yield from in_call_order(calls, ahead * workers, lambda call: task.remote(setup, call),
                             lambda waiting: _wait_for_first(ray, waiting), lambda ref: _get(ray, ref), deque())


def _wait_for_first(ray: Any, pending: deque) -> None:
    """Wait until the first call is done, raising at once the error of any later one
    (it would be raised anyway; no use waiting for the calls before it)."""
    first, waiting = pending[0], list(pending)
    while True:
        ready, waiting = ray.wait(waiting, num_returns=1, timeout=None, fetch_local=False)
        if first in ready:
            return
        _get(ray, ready[0])  # raises if that call failed


def _get(ray: Any, ref: Any) -> Any:
    """A task's result; an exception raised by ``fn`` is raised as itself (its type and
    message), with Ray's report of the worker's traceback as its cause."""
    try:
        return ray.get(ref)
    except ray.exceptions.RayTaskError as err:
        cause = getattr(err, "cause", None)
        if isinstance(cause, Exception):
            raise cause from err
        raise


# -- in a Ray worker process -----------------------------------------------------------------
_set_up: str | None = None


def _run_call(setup: tuple, call: tuple) -> Any:
    global _set_up
    token, fn, initializer, initargs = setup
    if _set_up != token:
        # llvmpipe renders in this thread, as in a process worker (read when the first
        # OpenGL context is made), whatever the first frame's profile.
        gl_backend.draw_in_calling_thread()
        if initializer is not None:
            initializer(*initargs)
        _set_up = token
    return fn(*call)
