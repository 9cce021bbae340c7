"""The Ray backend against the process backend: ``legent-gym collect`` with 2 workers each.

    python benchmarks/scale.py [--env Legent/ComeHere-OneRoom-v0] [--episodes 60] [--size 96]
                               [--rounds 2] [--workers 2] [--json]

Both collect the same expert episodes (same seeds, Minari + LEGENT formats) into a
temporary folder, in alternating rounds (process, Ray, process, Ray, ...) so that a change
in the machine's load hits both alike. Reported per backend, median over the rounds:

* ``traj/s``: expert trajectories committed per second of wall time, everything included
  (the process backend starts its worker processes in each run; the Ray workers start in
  the first Ray run, which is reported apart as ``ray-cold``, and are reused after);
* ``driver ms/ep``: CPU time of the driver (this process: taking results, committing
  episodes, progress) per episode; its inverse is the most episodes per second one driver
  commits, whatever the number of workers (``docs/scale.md``);
* ``ratio``: Ray's traj/s over the process backend's;
* ``kB/ep``: the output's size per episode (Minari + LEGENT formats).

The Ray cluster is started here (loopback, ``--workers`` CPUs, no dashboard) before the
first round; its start time is reported (``ray start s``), not counted in any rate.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from legent_gym.data import CollectConfig, collect  # noqa: E402
from legent_gym.scale import connect_ray  # noqa: E402


def run(env_id: str, episodes: int, size: int, workers: int, backend: str) -> dict:
    with tempfile.TemporaryDirectory(prefix="legent-scale-") as out:
        config = CollectConfig(env_id, episodes, out, formats=("minari", "legent"), workers=workers,
                               env_kwargs={"width": size, "height": size}, backend=backend)
        wall, cpu = time.perf_counter(), time.process_time()
        summary = collect(config, show_progress=False)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        size_bytes = sum(f.stat().st_size for f in Path(out).rglob("*") if f.is_file())
    return {"traj_s": summary.episodes / wall, "driver_ms_per_episode": 1000 * cpu / summary.episodes,
            "seconds": wall, "attempts": summary.attempts, "bytes_per_episode": size_bytes / summary.episodes}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--env", default="Legent/ComeHere-OneRoom-v0")
    p.add_argument("--episodes", type=int, default=60)
    p.add_argument("--size", type=int, default=96)
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    args = p.parse_args()

    began = time.perf_counter()
    connect_ray(None, args.workers)
    ray_start = time.perf_counter() - began
    cold = run(args.env, args.episodes, args.size, args.workers, "ray")
    rows: dict[str, list[dict]] = {"process": [], "ray": []}
    for _ in range(args.rounds):
        for backend in ("process", "ray"):
            rows[backend].append(run(args.env, args.episodes, args.size, args.workers, backend))

    def median(backend: str, key: str) -> float:
        return statistics.median(r[key] for r in rows[backend])

    result = {"env": args.env, "episodes": args.episodes, "size": args.size, "workers": args.workers,
              "rounds": args.rounds, "ray_start_s": ray_start, "cpus": len(os.sched_getaffinity(0)),
              "load_average": os.getloadavg()[0], "ray_cold": cold, "runs": rows,
              "process_traj_s": median("process", "traj_s"), "ray_traj_s": median("ray", "traj_s"),
              "process_driver_ms": median("process", "driver_ms_per_episode"),
              "ray_driver_ms": median("ray", "driver_ms_per_episode")}
    result["ratio"] = result["ray_traj_s"] / result["process_traj_s"]
    if args.json:
        print(json.dumps(result, indent=1))
        return 0
    print(f"{args.env}, {args.episodes} episodes at {args.size}x{args.size}, {args.workers} workers, "
          f"{args.rounds} rounds (load average {result['load_average']:.1f}); ray start {ray_start:.1f} s")
    print(f"{'backend':<10} {'traj/s':>8} {'driver ms/ep':>13}")
    print(f"{'process':<10} {result['process_traj_s']:8.2f} {result['process_driver_ms']:13.1f}")
    print(f"{'ray':<10} {result['ray_traj_s']:8.2f} {result['ray_driver_ms']:13.1f}")
    print(f"{'ray-cold':<10} {cold['traj_s']:8.2f} {cold['driver_ms_per_episode']:13.1f}")
    print(f"ratio ray / process: {result['ratio']:.2f}; output {cold['bytes_per_episode'] / 1000:.0f} kB/ep")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
