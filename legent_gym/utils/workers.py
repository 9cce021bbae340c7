"""Worker processes for work that renders: :func:`map_ordered`.

Every parallel loop of the project runs its calls through :func:`map_ordered`: data
collection (``legent-gym collect``), the VLA's evaluation and DAgger rollouts, training the
models of ``baselines/reproduce_table.py``, ``benchmarks/experts.py`` and the experts'
acceptance test. Each worker process

* is started by a ``forkserver``, never forked from this process (see
  ``docs/architecture.md``, "Processes and OpenGL");
* is pinned to one core, round robin over the cores this process may use
  (``os.sched_getaffinity(0)``), before it makes an OpenGL context, so that Mesa's
  llvmpipe renders in the worker's own thread and workers do not share a core while there
  are free ones;
* ignores Ctrl-C (this process gets it too and stops them all) and exits once this process
  is gone (killed with -9 it cannot tell them), instead of waiting for work forever.

Results come back in the order of the calls, whatever order the workers finish in, so a
caller that keeps them in that order gets the same whatever the number of workers::

    from legent_gym.utils.workers import map_ordered

    for result in map_ordered(fn, [(a, b), (c, d)], workers=2, progress="chunks"):
        ...  # fn(a, b), then fn(c, d)
"""

from __future__ import annotations

import contextlib
import multiprocessing
import multiprocessing.context
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Generator, Iterable, Iterator, Sized
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Any

from tqdm import tqdm

from legent_gym.utils import gl_backend
from legent_gym.utils.scale import Backend, in_call_order, ray_results

__all__ = ["map_ordered", "mp_context"]

#: How often a worker checks that the process that started it is still there (seconds).
PARENT_POLL_SECONDS = 1.0


def mp_context() -> multiprocessing.context.BaseContext:
    """The start method of every worker process (``forkserver``). Synchronisation objects
    handed to the workers (e.g. a ``Barrier`` in ``initargs``) must come from it."""
    return multiprocessing.get_context("forkserver")


def map_ordered(fn: Callable[..., Any], calls: Iterable[tuple], *, workers: int = 1,
                initializer: Callable[..., Any] | None = None, initargs: tuple = (),
                progress: bool | str = False, ahead: int = 2, pin: bool = True,
                backend: Backend | str | None = None) -> Iterator[Any]:
    """``fn(*call)`` for each argument tuple ``call`` of ``calls``, yielded in that order.

    ``workers == 1`` runs the calls in this process, one after another, and does not run
    ``initializer`` (this process is set up already). ``workers > 1`` runs them in that many
    worker processes (see the module's docstring), each of which runs
    ``initializer(*initargs)`` once before its first call; ``fn``, the calls, the initializer
    and its arguments are pickled to reach them (module-level functions, plain data).

    At most ``ahead * workers`` calls are handed out beyond the last result yielded, so
    ``calls`` may be a long or endless iterator and a consumer may stop early. ``progress``
    (``True`` or a description) shows a tqdm bar of the calls done. ``pin=False`` leaves the
    workers on all cores (for work that runs threads of its own).

    An exception raised by a call, or by the initializer, is raised here as soon as it
    happens (not after the calls before it), with its message and the worker's traceback as
    its cause. On any exception, on Ctrl-C, or when the
    consumer stops early (the generator is closed), the pending calls are cancelled and the
    workers stopped before the exception goes on (the Ray backend leaves its calls in flight
    to finish unread: see :func:`legent_gym.utils.scale.ray_results`).

    ``backend`` (:mod:`legent_gym.utils.scale`): ``"process"`` (the default, as above) or
    ``"ray"`` / a :class:`~legent_gym.utils.scale.Backend` with a Ray address: the calls run as
    Ray tasks under the same contract (order, ``ahead``, errors); a Ray started here has
    ``workers`` CPUs, so ``workers`` run at a time; on a cluster, as many of the
    ``ahead * workers`` in flight as it has free CPUs. ``workers == 1`` runs them as Ray
    tasks too.
    """
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    if ahead < 1:
        raise ValueError(f"ahead must be >= 1, got {ahead}")
    total = len(calls) if isinstance(calls, Sized) else None
    results: Generator[Any, None, None]
    where = Backend.of(backend)
    if where.kind == "ray":
        results = ray_results(fn, calls, workers=workers, initializer=initializer, initargs=initargs,
                              ahead=ahead, address=where.address)
    elif workers == 1:
        results = (fn(*call) for call in calls)
    else:
        results = _in_workers(fn, calls, workers, initializer, initargs, ahead, pin)
    return _counted(results, progress, total)


def _counted(results: Generator[Any, None, None], progress: bool | str, total: int | None) -> Iterator[Any]:
    with tqdm(total=total, desc=progress if isinstance(progress, str) else None, disable=not progress,
              unit="call") as bar:
        try:
            for result in results:
                yield result
                bar.update(1)
        finally:
            results.close()  # stops the workers now if the consumer stopped early


def _in_workers(fn, calls, workers, initializer, initargs, ahead, pin) -> Generator[Any, None, None]:
    ctx = mp_context()
    cores = sorted(os.sched_getaffinity(0)) if pin and hasattr(os, "sched_setaffinity") else []
    crew = _Crew(ctx, workers, cores)
    pool = ProcessPoolExecutor(workers, mp_context=ctx, initializer=_start_worker,
                               initargs=(os.getpid(), crew, initializer, initargs))
    pending: deque = deque()
    finished = False
    try:
        yield from in_call_order(calls, ahead * workers, lambda call: pool.submit(_call, fn, call), _wait_for_first,
                                 lambda future: future.result(), pending)
        finished = True
    finally:
        if finished:
            pool.shutdown(wait=True)
        else:
            _stop(pool, crew)


def _wait_for_first(pending: deque) -> None:
    """Wait until the first call is done, raising at once the error of any later one
    (it would be raised anyway; no use waiting for the calls before it)."""
    while not pending[0].done():
        done, _ = wait([f for f in pending if not f.done()], return_when=FIRST_COMPLETED)
        for future in done:
            if future.exception() is not None:
                future.result()


class _Crew:
    """What the workers of one pool share with this process: how many have started (worker
    k takes core k), their pids (to stop them) and a stop flag (for one still starting)."""

    def __init__(self, ctx: multiprocessing.context.BaseContext, workers: int, cores: list[int]):
        self.cores = cores
        self.started = ctx.Value("i", 0)
        self.pids = ctx.Array("i", workers)
        self.stopped = ctx.Event()


def _stop(pool: ProcessPoolExecutor, crew: _Crew) -> None:
    """Cancel what has not started and end the workers now: a running call may take minutes
    (a training run), and what it would return is not wanted any more. Every worker goes,
    not only the busy ones: one killed while reading the pool's queue of calls leaves its
    lock taken, and the others would wait for it forever."""
    with crew.started.get_lock():  # a worker that starts after this sees the flag and leaves
        crew.stopped.set()
        pids = [pid for pid in crew.pids[:] if pid]
    for pid in pids:
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGTERM)
    # The pool sees its workers gone, fails what was running and stops.
    pool.shutdown(wait=True, cancel_futures=True)


# -- in the worker ---------------------------------------------------------------------------
_init_error: BaseException | None = None


def _start_worker(parent_pid: int, crew: _Crew, initializer, initargs) -> None:
    global _init_error
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent handles Ctrl-C and stops us
    threading.Thread(target=_exit_with, args=(parent_pid,), daemon=True, name="parent-watch").start()
    with crew.started.get_lock():
        stopped = crew.stopped.is_set()
        index = crew.started.value
        if not stopped and index < len(crew.pids):
            crew.started.value += 1
            crew.pids[index] = os.getpid()
    if stopped:
        os._exit(0)  # the parent stopped the pool while this worker was starting
    if crew.cores:
        os.sched_setaffinity(0, {crew.cores[index % len(crew.cores)]})
        # llvmpipe sizes its thread pool to the cores it may use (one now); say so for a
        # Mesa that does not look at the affinity, and whatever the first frame's profile.
        gl_backend.draw_in_calling_thread()
    if initializer is not None:
        try:
            initializer(*initargs)
        except Exception as err:  # raised by every call, so the parent sees the message
            _init_error = err


def _call(fn, args):
    if _init_error is not None:
        raise _init_error
    return fn(*args)


def _exit_with(parent_pid: int) -> None:
    """Leave when the parent is gone: an orphaned worker would otherwise wait for work
    forever and keep the forkserver alive."""
    while True:
        time.sleep(PARENT_POLL_SECONDS)
        try:
            os.kill(parent_pid, 0)
        except ProcessLookupError:
            os._exit(0)
