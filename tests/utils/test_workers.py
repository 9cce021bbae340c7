"""legent_gym.utils.workers.map_ordered: order, pinning, errors, progress, stopping, orphans."""

from __future__ import annotations

import itertools
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from legent_gym.utils.workers import map_ordered, mp_context

REPO = Path(__file__).resolve().parents[2]
needs_affinity = pytest.mark.skipif(not hasattr(os, "sched_setaffinity"), reason="no CPU affinity here")

# -- run in the workers (module level, so they pickle) ---------------------------------------
_barrier = None


def _keep_barrier(barrier) -> None:
    global _barrier
    _barrier = barrier


def _where(i: int) -> tuple[int, int, list[int], str | None]:
    _barrier.wait(timeout=60)  # every call in a worker of its own
    return i, os.getpid(), sorted(os.sched_getaffinity(0)), os.environ.get("LP_NUM_THREADS")


def _square_after(x: int, seconds: float) -> int:
    time.sleep(seconds)
    return x * x


def _fail_on(x: int, bad: int, seconds: float) -> int:
    if x == bad:
        raise ValueError(f"cannot take {x}")
    time.sleep(seconds)
    return x


def _broken_initializer() -> None:
    raise RuntimeError("no checkpoint at nowhere.pt")


# -- tests -----------------------------------------------------------------------------------
def test_results_come_in_the_order_of_the_calls():
    # The first calls take longest, so the workers finish them last.
    calls = [(x, 0.05 * (5 - x)) for x in range(6)]
    assert list(map_ordered(_square_after, calls, workers=2)) == [x * x for x in range(6)]
    assert list(map_ordered(_square_after, calls, workers=1)) == [x * x for x in range(6)]
    assert list(map_ordered(_square_after, iter(calls), workers=2, ahead=1)) == [x * x for x in range(6)]


@needs_affinity
def test_each_worker_is_pinned_to_its_own_core_round_robin():
    cores = sorted(os.sched_getaffinity(0))
    barrier = mp_context().Barrier(2)
    results = list(map_ordered(_where, [(0,), (1,)], workers=2, initializer=_keep_barrier, initargs=(barrier,)))
    assert [i for i, *_ in results] == [0, 1]
    assert len({pid for _, pid, _, _ in results}) == 2 and os.getpid() not in {pid for _, pid, _, _ in results}
    assert sorted(affinity for _, _, affinity, _ in results) == [[cores[0]], [cores[1 % len(cores)]]]
    if "LP_NUM_THREADS" not in os.environ:
        assert {lp for *_, lp in results} == {"0"}  # llvmpipe draws in the worker's own thread
    assert sorted(os.sched_getaffinity(0)) == cores  # this process is left as it was

    barrier = mp_context().Barrier(2)
    unpinned = list(map_ordered(_where, [(0,), (1,)], workers=2, initializer=_keep_barrier, initargs=(barrier,),
                                pin=False))
    assert [affinity for _, _, affinity, _ in unpinned] == [cores, cores]


def test_an_error_in_a_worker_is_raised_here_with_its_message_and_stops_the_rest():
    calls = [(x, 1, 60.0) for x in range(4)]  # call 1 fails at once; the others would take a minute
    began = time.monotonic()
    with pytest.raises(ValueError, match="cannot take 1") as raised:
        list(map_ordered(_fail_on, calls, workers=2))
    assert time.monotonic() - began < 30, "waited for the running calls instead of stopping them"
    assert "_fail_on" in str(raised.value.__cause__)  # the worker's traceback
    with pytest.raises(ValueError, match="cannot take 1"):
        list(map_ordered(_fail_on, [(x, 1, 0.0) for x in range(4)], workers=1))


def test_an_error_in_the_initializer_is_raised_with_its_message():
    with pytest.raises(RuntimeError, match="no checkpoint at nowhere.pt"):
        list(map_ordered(_square_after, [(1, 0.0), (2, 0.0)], workers=2, initializer=_broken_initializer))


def test_a_consumer_may_stop_early_even_on_endless_calls():
    began = time.monotonic()
    results = map_ordered(_square_after, ((x, 0.01 if x < 3 else 60.0) for x in itertools.count()), workers=2)
    assert [next(results) for _ in range(3)] == [0, 1, 4]
    results.close()  # the workers are busy with a minute-long call each: stopped, not awaited
    assert time.monotonic() - began < 30


def test_progress_bar_off_by_default_and_on_when_asked(capsys):
    calls = [(x, 0.0) for x in range(3)]
    assert list(map_ordered(_square_after, calls)) == [0, 1, 4]
    assert capsys.readouterr().err == ""
    assert list(map_ordered(_square_after, calls, workers=2, progress="squares")) == [0, 1, 4]
    err = capsys.readouterr().err
    assert "squares" in err and "3/3" in err


def test_bad_arguments_are_refused_before_anything_starts():
    with pytest.raises(ValueError, match="workers must be >= 1"):
        map_ordered(_square_after, [], workers=0)
    with pytest.raises(ValueError, match="ahead must be >= 1"):
        map_ordered(_square_after, [], workers=2, ahead=0)
    assert list(map_ordered(_square_after, [], workers=2)) == []


def _pid_file_then_sleep(folder: str, i: int) -> None:
    Path(folder, f"{i}.pid").write_text(str(os.getpid()))
    time.sleep(120)


def _start_sleepers(tmp_path: Path) -> tuple[subprocess.Popen, list[int]]:
    """A process (a session of its own) whose two workers are asleep in a call; their pids."""
    script = textwrap.dedent(f"""
        import faulthandler, signal, sys
        # A terminal's process: Ctrl-C raises KeyboardInterrupt. One started by a process that
        # ignores SIGINT inherits the ignoring; the first line of stderr says which it was.
        print("SIGINT on start:", signal.getsignal(signal.SIGINT), file=sys.stderr, flush=True)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        faulthandler.dump_traceback_later(90)  # a hang shows on stderr where each thread waits
        from tests.utils.test_workers import _pid_file_then_sleep
        from legent_gym.utils.workers import map_ordered
        list(map_ordered(_pid_file_then_sleep, [({str(tmp_path)!r}, 0), ({str(tmp_path)!r}, 1)], workers=2))
    """)
    proc = subprocess.Popen([sys.executable, "-c", script], cwd=REPO, start_new_session=True,
                            stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while len(list(tmp_path.glob("*.pid"))) < 2 and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.05)
    return proc, [int(p.read_text()) for p in tmp_path.glob("*.pid")]


def _gone(pids: list[int], timeout: float) -> bool:
    deadline = time.monotonic() + timeout
    while any(_alive(pid) for pid in pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    return not any(_alive(pid) for pid in pids)


@pytest.mark.parametrize("how", ["kill -9", "Ctrl-C"])
def test_workers_end_with_their_parent(tmp_path, how):
    proc, pids = _start_sleepers(tmp_path)
    try:
        assert len(pids) == 2, proc.stderr.read() if proc.poll() is not None else "no workers"
        if how == "kill -9":  # the parent cannot tell them: they notice it is gone
            os.kill(proc.pid, signal.SIGKILL)
            proc.wait()
        else:  # the terminal's Ctrl-C reaches the whole group; the parent stops the workers
            os.killpg(proc.pid, signal.SIGINT)
            # seconds, not minutes, alone; a loaded 2-core machine has taken over 30
            try:
                code = proc.wait(timeout=120)
            except subprocess.TimeoutExpired:
                proc.kill()
                pytest.fail(f"the parent did not end within 120 s of Ctrl-C; its stderr:\n{proc.stderr.read()}")
            assert code != 0
            assert proc.stderr.read().count("KeyboardInterrupt") == 1  # the parent's, not one per worker
        assert _gone(pids, timeout=15)
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.stderr.close()
        for pid in pids:  # only the workers this test started
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # A zombie is gone for our purpose (its parent, the forkserver, reaps it later).
    try:
        return Path(f"/proc/{pid}/stat").read_text().split(") ")[-1][0] != "Z"
    except OSError:
        return False
