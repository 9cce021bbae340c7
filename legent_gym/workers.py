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

    from legent_gym.workers import map_ordered

    for result in map_ordered(fn, [(a, b), (c, d)], workers=2, progress="chunks"):
        ...  # fn(a, b), then fn(c, d)
"""

from __future__ import annotations

import multiprocessing
import multiprocessing.context
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Any

__all__ = ["map_ordered", "mp_context"]

#: How often a worker checks that the process that started it is still there (seconds).
PARENT_POLL_SECONDS = 1.0


def mp_context() -> multiprocessing.context.BaseContext:
    """The start method of every worker process (``forkserver``). Synchronisation objects
    handed to the workers (e.g. a ``Barrier`` in ``initargs``) must come from it."""
    return multiprocessing.get_context("forkserver")


def map_ordered(fn: Callable[..., Any], calls: Iterable[tuple], *, workers: int = 1,
                initializer: Callable[..., Any] | None = None, initargs: tuple = (),
                progress: bool | str = False, ahead: int = 2, pin: bool = True) -> Iterator[Any]:
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
    workers stopped before the exception goes on.
    """
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    if ahead < 1:
        raise ValueError(f"ahead must be >= 1, got {ahead}")
    total = len(calls) if hasattr(calls, "__len__") else None
    if workers == 1:
        results = (fn(*call) for call in calls)
    else:
        results = _in_workers(fn, calls, workers, initializer, initargs, ahead, pin)
    return _counted(results, progress, total)


def _counted(results: Iterator[Any], progress: bool | str, total: int | None) -> Iterator[Any]:
    from tqdm import tqdm

    with tqdm(total=total, desc=progress if isinstance(progress, str) else None, disable=not progress,
              unit="call") as bar:
        try:
            for result in results:
                yield result
                bar.update(1)
        finally:
            results.close()  # stops the workers now if the consumer stopped early


def _in_workers(fn, calls, workers, initializer, initargs, ahead, pin) -> Iterator[Any]:
    ctx = mp_context()
    cores = sorted(os.sched_getaffinity(0)) if pin and hasattr(os, "sched_setaffinity") else []
    pool = ProcessPoolExecutor(workers, mp_context=ctx, initializer=_start_worker,
                               initargs=(os.getpid(), cores, ctx.Value("i", 0), initializer, initargs))
    pending: deque = deque()
    calls = iter(calls)
    finished = False
    try:
        while True:
            while len(pending) < ahead * workers:
                call = next(calls, None)
                if call is None:
                    break
                pending.append(pool.submit(_call, fn, tuple(call)))
            if not pending:
                break
            _wait_for_first(pending)
            yield pending.popleft().result()
        finished = True
    finally:
        if finished:
            pool.shutdown(wait=True)
        else:
            _stop(pool)


def _wait_for_first(pending: deque) -> None:
    """Wait until the first call is done, raising at once the error of any later one
    (it would be raised anyway; no use waiting for the calls before it)."""
    while not pending[0].done():
        done, _ = wait([f for f in pending if not f.done()], return_when=FIRST_COMPLETED)
        for future in done:
            if future.exception() is not None:
                future.result()


def _stop(pool: ProcessPoolExecutor) -> None:
    """Cancel what has not started and end the workers now: a running call may take minutes
    (a training run), and what it would return is not wanted any more."""
    if hasattr(pool, "terminate_workers"):  # Python >= 3.14
        pool.terminate_workers()
        return
    processes = list((pool._processes or {}).values())
    manager = pool._executor_manager_thread
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join()
    if manager is not None:
        manager.join()  # it sees the workers gone, fails what was running and stops


# -- in the worker ---------------------------------------------------------------------------
_init_error: BaseException | None = None


def _start_worker(parent_pid: int, cores: list[int], counter, initializer, initargs) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent handles Ctrl-C and stops us
    threading.Thread(target=_exit_with, args=(parent_pid,), daemon=True, name="parent-watch").start()
    if cores:
        with counter.get_lock():
            index = counter.value
            counter.value += 1
        os.sched_setaffinity(0, {cores[index % len(cores)]})
        # llvmpipe sizes its thread pool to the cores it may use (one now); say so for a
        # Mesa that does not look at the affinity. Same images either way.
        os.environ.setdefault("LP_NUM_THREADS", "0")
    if initializer is not None:
        try:
            initializer(*initargs)
        except Exception as err:  # raised by every call, so the parent sees the message
            global _init_error
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
