"""Expert speed: expert actions/s and successful trajectories/s per env id, one and two workers.

    python benchmarks/experts.py [--ids Legent/ComeHere-OneRoom-v0,...] [--attempts 40] [--size 96]
                                 [--workers 1,2] [--collect-ids Legent/ComeHere-OneRoom-v0]

Each attempt is what ``legent-gym collect`` does for one episode without writing it: a
reset with a new house (seed ``k``), then the expert's action (``ExpertInfo``) at every
step until the episode ends. Reported per env id and worker count:

* ``act/s``: actions executed per second, everything included (resets too);
* ``traj/s``: successful trajectories per second (the collection rate);
* ``traj/cpu-s``: the same per second of CPU time used (all workers together): on a
  machine shared with other jobs, the rate an idle core would give;
* ``expert ms``: the expert's own planning time per action (median), from the same run;
* ``reset ms``: the median reset (generation + build + navigation grid + first frame);
* ``success``, ``act/ep``: the expert's success rate and mean actions per episode.

One worker runs pinned to one core; two workers are two worker processes of
``legent_gym.utils.workers`` (one core each) measured from a common start after their first reset.
``--collect-ids`` also times the whole ``legent-gym collect`` pipeline (Minari + LEGENT
export, one worker, one core).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import gymnasium as gym
from benchmarks_common import pin_to_one_core, write_report

import legent_gym
from legent_gym.utils.workers import map_ordered, mp_context
from legent_gym.wrappers.expert import ExpertInfo


class TimedExpertInfo(ExpertInfo):
    """``ExpertInfo`` that keeps the time of each expert call."""

    def __init__(self, env):
        super().__init__(env)
        self.expert_seconds: list[float] = []

    def _label(self, info):
        start = time.perf_counter()
        labelled = super()._label(info)
        self.expert_seconds.append(time.perf_counter() - start)
        return labelled


def run_attempts(env_id: str, size: int, seeds: range, barrier=None) -> dict:
    env = TimedExpertInfo(gym.make(env_id, width=size, height=size))
    env.reset(seed=10**6)  # the first reset builds the GL context: not part of the rate
    env.expert_seconds.clear()
    if barrier is not None:
        barrier.wait()
    actions = successes = 0
    reset_seconds = []
    start, cpu_start = time.perf_counter(), time.process_time()
    for seed in seeds:
        began = time.perf_counter()
        _, info = env.reset(seed=seed)
        reset_seconds.append(time.perf_counter() - began)
        while True:
            _, _, terminated, truncated, info = env.step(info["expert_action"])
            actions += 1
            if terminated or truncated:
                break
        successes += bool(info["success"])
    end, cpu = time.perf_counter(), time.process_time() - cpu_start
    env.close()
    return {"start": start, "end": end, "cpu": cpu, "attempts": len(seeds), "actions": actions, "successes": successes,
            "expert_s": env.expert_seconds, "reset_s": reset_seconds}


def _summarise(parts: list[dict]) -> dict:
    wall = max(p["end"] for p in parts) - min(p["start"] for p in parts)
    actions = sum(p["actions"] for p in parts)
    successes = sum(p["successes"] for p in parts)
    attempts = sum(p["attempts"] for p in parts)
    expert = [t for p in parts for t in p["expert_s"]]
    resets = [t for p in parts for t in p["reset_s"]]
    return {"actions_per_s": actions / wall, "trajectories_per_s": successes / wall,
            "trajectories_per_cpu_s": successes / sum(p["cpu"] for p in parts),
            "expert_ms": 1e3 * statistics.median(expert), "reset_ms": 1e3 * statistics.median(resets),
            "success_rate": successes / attempts, "actions_per_episode": actions / attempts}


_barrier = None


def _keep_barrier(barrier) -> None:
    global _barrier
    _barrier = barrier


def _run_share(env_id: str, size: int, seeds: range) -> dict:
    return run_attempts(env_id, size, seeds, _barrier)


def bench(env_id: str, size: int, attempts: int, workers: int) -> dict:
    if workers == 1:
        return _summarise([run_attempts(env_id, size, range(attempts))])
    # One share per worker (each waits at the barrier for the others, so no worker takes two),
    # each worker on a core of its own.
    share = -(-attempts // workers)
    shares = [(env_id, size, range(i * share, min(attempts, (i + 1) * share))) for i in range(workers)]
    return _summarise(list(map_ordered(_run_share, shares, workers=workers, initializer=_keep_barrier,
                                       initargs=(mp_context().Barrier(workers),))))


@contextlib.contextmanager
def one_core():
    affinity = os.sched_getaffinity(0)
    pin_to_one_core()
    try:
        yield
    finally:
        os.sched_setaffinity(0, affinity)


def bench_collect(env_id: str, size: int, episodes: int) -> dict:
    from legent_gym.data import CollectConfig, collect

    with tempfile.TemporaryDirectory() as tmp:
        def run(out: str, n: int):
            return collect(CollectConfig(env_id, n, out, formats=("minari", "legent"),
                                         env_kwargs={"width": size, "height": size}), show_progress=False)

        run(str(Path(tmp) / "warm-up"), 1)  # imports, the GL context
        cpu_start = time.process_time()
        summary = run(str(Path(tmp) / "run"), episodes)
        cpu = time.process_time() - cpu_start
    return {"trajectories_per_s": summary.episodes_per_second, "trajectories_per_cpu_s": summary.episodes / cpu,
            "success_rate": summary.success_rate}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ids", default=",".join(legent_gym.ENV_IDS))
    parser.add_argument("--attempts", type=int, default=40)
    parser.add_argument("--size", type=int, default=96)
    parser.add_argument("--workers", default="1,2")
    parser.add_argument("--collect-ids", default="Legent/ComeHere-OneRoom-v0")
    parser.add_argument("--json", help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    load_before = os.getloadavg()[0]
    worker_counts = [int(w) for w in args.workers.split(",")]
    results = {}
    print(f"{'env id':34s} {'workers':>7} {'act/s':>7} {'traj/s':>7} {'traj/cpu-s':>10} {'expert ms':>9} "
          f"{'reset ms':>8} {'success':>7} {'act/ep':>6}")
    for env_id in args.ids.split(","):
        for workers in worker_counts:
            with one_core() if workers == 1 else contextlib.nullcontext():
                r = bench(env_id, args.size, args.attempts, workers)
            results[f"{env_id} x{workers}"] = r
            print(f"{env_id:34s} {workers:>7} {r['actions_per_s']:>7.1f} {r['trajectories_per_s']:>7.2f} "
                  f"{r['trajectories_per_cpu_s']:>10.2f} {r['expert_ms']:>9.2f} {r['reset_ms']:>8.1f} {r['success_rate']:>7.0%} "
                  f"{r['actions_per_episode']:>6.1f}")
    for env_id in filter(None, args.collect_ids.split(",")):
        with one_core():
            r = bench_collect(env_id, args.size, args.attempts)
        results[f"{env_id} collect x1"] = r
        print(f"{env_id:34s} collect (minari+legent, 1 worker): {r['trajectories_per_s']:.2f} traj/s, "
              f"{r['trajectories_per_cpu_s']:.2f} traj/cpu-s, success {r['success_rate']:.0%}")
    if args.json:
        write_report(args.json, args, results, load_before)
    return 0


if __name__ == "__main__":
    sys.exit(main())
