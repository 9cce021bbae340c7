"""The Ray backend against the process backend: ``legent-gym collect`` with 2 workers each.

    python benchmarks/scale.py [--env Legent/ComeHere-OneRoom-v0] [--episodes 60] [--size 96]
                               [--rounds 2] [--workers 2] [--json]

Both collect the same expert episodes (same seeds, Minari + LEGENT formats) into a
temporary folder. Each round runs the process backend, then starts a Ray on this machine
(loopback, ``--workers`` CPUs, no dashboard; its start time is reported as ``ray start s``
and counted in no rate), runs the Ray backend twice and stops Ray, so that a change in the
machine's load hits every row alike. Reported per row, median over the rounds:

* ``traj/s``: expert trajectories committed per second of wall time, everything included:
  ``process`` starts its worker processes in the run, ``ray-cold`` is the first Ray run
  after the start (its workers start in the run, like the process backend's),
  ``ray-warm`` the second (its workers are up);
* ``driver ms/ep``: CPU time of the driver (this process: taking results, committing
  episodes, progress) per episode; its inverse is the most episodes per second one driver
  commits, whatever the number of workers (``docs/scale.md``);
* ``ratio``: each Ray row's traj/s over the process backend's, median of the rounds' ratios;
* ``kB/ep``: the output's size per episode (Minari + LEGENT formats).
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
from legent_gym.utils.scale import connect_ray  # noqa: E402


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

    rows: dict[str, list[dict]] = {"process": [], "ray-cold": [], "ray-warm": []}
    starts = []
    for _ in range(args.rounds):
        rows["process"].append(run(args.env, args.episodes, args.size, args.workers, "process"))
        began = time.perf_counter()
        ray = connect_ray(None, args.workers)
        starts.append(time.perf_counter() - began)
        rows["ray-cold"].append(run(args.env, args.episodes, args.size, args.workers, "ray"))
        rows["ray-warm"].append(run(args.env, args.episodes, args.size, args.workers, "ray"))
        ray.shutdown()

    def median(row: str, key: str) -> float:
        return statistics.median(r[key] for r in rows[row])

    def ratio(row: str) -> float:
        return statistics.median(r["traj_s"] / p["traj_s"] for r, p in zip(rows[row], rows["process"]))

    result = {"env": args.env, "episodes": args.episodes, "size": args.size, "workers": args.workers,
              "rounds": args.rounds, "ray_start_s": statistics.median(starts), "cpus": len(os.sched_getaffinity(0)),
              "load_average": os.getloadavg()[0], "runs": rows,
              "traj_s": {row: median(row, "traj_s") for row in rows},
              "driver_ms_per_episode": {row: median(row, "driver_ms_per_episode") for row in rows},
              "ratio": {row: ratio(row) for row in ("ray-cold", "ray-warm")},
              "bytes_per_episode": median("process", "bytes_per_episode")}
    if args.json:
        print(json.dumps(result, indent=1))
        return 0
    print(f"{args.env}, {args.episodes} episodes at {args.size}x{args.size}, {args.workers} workers, "
          f"{args.rounds} rounds (load average {result['load_average']:.1f}); ray start "
          f"{result['ray_start_s']:.1f} s; output {result['bytes_per_episode'] / 1000:.0f} kB/ep")
    print(f"{'backend':<10} {'traj/s':>8} {'driver ms/ep':>13} {'ratio':>6}")
    for row in rows:
        shown = f"{result['ratio'][row]:6.2f}" if row in result["ratio"] else f"{'':>6}"
        print(f"{row:<10} {result['traj_s'][row]:8.2f} {result['driver_ms_per_episode'][row]:13.1f} {shown}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
