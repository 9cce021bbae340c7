"""House generation speed: houses/s for 1, 2, 4 and 6 rooms, split into its stages.

    python benchmarks/generation.py [--houses 30]
    python benchmarks/generation.py --plans [--houses 10]

For each room count, on one core: median milliseconds of generation (scene JSON), MuJoCo
build (scene -> compiled model), and the navigation grid; their sum and houses/s; then the
median shortest-path query time (random walkable start and goal pairs on the same houses).
The reference measured in the same run is the MuJoCo compile of the same scenes alone.

``--plans``: each plan of ``examples/plans/`` solved into a scene (``solve_plan``, seeds
0..N-1, no LLM), median milliseconds and objects placed, beside the procedural FourRoom
generation of the same number of seeds in the same run (the ratio: plan / FourRoom).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np
from benchmarks_common import pin_to_one_core, write_report

import legent_gym  # noqa: F401
from legent_gym.world.builder import build_spec
from legent_gym.world.generation import generate_house
from legent_gym.world.navigation import NavGrid

SPECS = {1: "OneRoom", 2: "TwoRoom", 4: "FourRoom", 6: {"n_rooms": 6}}


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, (time.perf_counter() - start) * 1e3


def bench(n_rooms: int, houses: int) -> dict:
    spec = SPECS[n_rooms]
    gen, build, compile_only, nav, paths = [], [], [], [], []
    rng = np.random.default_rng(0)
    for seed in range(houses):
        if isinstance(spec, str):
            scene, ms = timed(lambda s=seed: generate_house(s, spec))
        else:
            scene, ms = timed(lambda s=seed: generate_house(s, **spec))
        gen.append(ms)
        (model_spec, _), ms_spec = timed(lambda sc=scene: build_spec(sc))
        _, ms_compile = timed(model_spec.compile)
        build.append(ms_spec + ms_compile)
        compile_only.append(ms_compile)
        grid, ms = timed(lambda sc=scene: NavGrid.from_scene(sc))
        nav.append(ms)
        cells = np.argwhere(grid.walkable)
        for _ in range(20):
            a, b = cells[rng.integers(len(cells), size=2)]
            _, ms = timed(lambda a=a, b=b, g=grid: g.path(g.to_world(a), g.to_world(b)))
            paths.append(ms)
    med = statistics.median
    total = med([g + b + n for g, b, n in zip(gen, build, nav)])
    return {"gen": med(gen), "build": med(build), "compile": med(compile_only), "nav": med(nav),
            "total": total, "houses_per_s": 1000 / total, "path": med(paths), "path_p95": float(np.percentile(paths, 95))}


def bench_plans(seeds: int) -> None:
    """Median solve time of each example plan against FourRoom generation, same run."""
    import json
    from pathlib import Path

    from legent_gym.world.generation.conditions import Catalog
    from legent_gym.world.generation.plan import solve_plan

    catalog = Catalog.from_registry()
    plans = sorted((Path(__file__).resolve().parents[1] / "examples" / "plans").glob("*.json"))
    reference = statistics.median(timed(lambda s=s: generate_house(s, "FourRoom"))[1] for s in range(seeds))
    print(f"FourRoom generation (reference): {reference:.1f} ms median over {seeds} seeds")
    print(f"{'plan':>18} {'rooms':>5} {'objects':>7} {'solve ms':>9} {'x FourRoom':>10}")
    for path in plans:
        plan = json.loads(path.read_text())
        solve_plan(plan, 10_000, catalog)  # warm: the asset models its objects use
        runs = [timed(lambda s=s, p=plan: solve_plan(p, s, catalog)) for s in range(seeds)]
        ms = statistics.median(t for _, t in runs)
        placed = statistics.median(len(solved.scene.objects) for solved, _ in runs)
        print(f"{path.stem:>18} {len(plan['rooms']):>5} {placed:>7.0f} {ms:>9.1f} {ms / reference:>10.2f}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--houses", type=int, default=30)
    parser.add_argument("--rooms", default="1,2,4,6")
    parser.add_argument("--plans", action="store_true", help="solve the example plans instead (seeds: --houses)")
    parser.add_argument("--json", metavar="OUT", help="also write the figures to this JSON file (not with --plans)")
    args = parser.parse_args(argv)
    load_before = os.getloadavg()[0]
    pin_to_one_core()
    generate_house(0, "OneRoom")  # warm caches (asset models) before timing
    if args.plans:
        bench_plans(args.houses)
        return 0
    print(f"{'rooms':>5} {'gen ms':>7} {'build ms':>9} {'(compile)':>9} {'nav ms':>7} {'total ms':>9} "
          f"{'houses/s':>9} {'path ms':>8} {'p95':>6}")
    rows = {}
    for n in (int(x) for x in args.rooms.split(",")):
        r = bench(n, args.houses)
        print(f"{n:>5} {r['gen']:>7.1f} {r['build']:>9.1f} {r['compile']:>9.1f} {r['nav']:>7.1f} {r['total']:>9.1f} "
              f"{r['houses_per_s']:>9.1f} {r['path']:>8.2f} {r['path_p95']:>6.2f}")
        rows[str(n)] = r
    if args.json:
        write_report(args.json, args, rows, load_before)
    return 0


if __name__ == "__main__":
    sys.exit(main())
